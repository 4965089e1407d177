// The viewer's controls, shared by the notebook widget and the `rasterkit view` page: the
// mouse on the picture becomes viewer events (rasterkit/viewer/session.py lists them), and a
// small bar switches the mode, the shading and the map shown.

// Mouse moves are sent one message at a time: while one is on its way, the next ones are
// added up into one (no queue builds up when the connection is slower than the mouse).
export function sender(post) {
  let busy = false, pending = null, seq = 0;
  const sent = new Map();  // seq -> time sent (the page's latency figures)
  function merge(a, b) {
    if (a && a.kind === b.kind && b.kind === 'drag' && a.pan === b.pan) {
      return {...b, dx: a.dx + b.dx, dy: a.dy + b.dy};
    }
    if (a && a.kind === b.kind && b.kind === 'wheel') return {...b, steps: a.steps + b.steps};
    return null;
  }
  async function flush() {
    while (pending && !busy) {
      const event = pending.shift();
      if (!pending.length) pending = null;
      busy = true;
      event.seq = ++seq;
      sent.set(event.seq, performance.now());
      try { await post(event); } catch (e) { console.warn('rasterkit viewer:', e); }
      busy = false;
    }
  }
  function send(event) {
    if (pending) {
      const merged = merge(pending[pending.length - 1], event);
      if (merged) pending[pending.length - 1] = merged; else pending.push(event);
    } else {
      pending = [event];
    }
    flush();
  }
  return {send, sent};
}

// Pointer, wheel and double-click on `surface`; `scale()` is image pixels per CSS pixel.
export function attach(surface, send, scale) {
  let drag = null;
  surface.addEventListener('contextmenu', e => e.preventDefault());
  surface.addEventListener('pointerdown', e => {
    drag = {x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 || e.button === 1};
    surface.setPointerCapture(e.pointerId);
    e.preventDefault();
  });
  surface.addEventListener('pointermove', e => {
    if (!drag) return;
    const k = scale(), dx = (e.clientX - drag.x) * k, dy = (e.clientY - drag.y) * k;
    drag.x = e.clientX; drag.y = e.clientY;
    if (dx || dy) send({kind: 'drag', dx, dy, pan: drag.pan});
  });
  const end = () => { if (drag) { drag = null; send({kind: 'release'}); } };
  surface.addEventListener('pointerup', end);
  surface.addEventListener('pointercancel', end);
  surface.addEventListener('wheel', e => {
    e.preventDefault();
    const lines = e.deltaMode === 1 ? 3 : e.deltaMode === 2 ? 100 : 100;  // lines, pages, pixels
    send({kind: 'wheel', steps: e.deltaY / lines});
  }, {passive: false});
  surface.addEventListener('dblclick', () => send({kind: 'reframe'}));
}

// The bar: a select for each of mode, shading and show, from `choices` ({mode: [...], ...})
// set to `current`; a change sends a `set` event.
export function bar(element, choices, current, send) {
  for (const key of ['mode', 'shading', 'show']) {
    const label = document.createElement('label');
    label.textContent = key + ' ';
    const select = document.createElement('select');
    select.name = key;
    for (const choice of choices[key]) {
      const option = document.createElement('option');
      option.value = option.textContent = choice;
      option.selected = choice === current[key];
      select.append(option);
    }
    select.addEventListener('change', () => send({kind: 'set', [key]: select.value}));
    label.append(select);
    element.append(label);
  }
}
