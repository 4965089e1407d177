// The notebook widget's page side (anywidget): frames arrive as custom messages with the
// picture in a binary buffer, events go back as custom messages. An event waits for the
// frame that shows it (or a second) before the next one goes, so the kernel never works
// through a backlog of old mouse moves.
export default {
  render({model, el}) {
    const root = document.createElement('div');
    root.className = 'rasterkit-viewer';
    const strip = document.createElement('div');
    strip.className = 'rk-bar';
    const image = document.createElement('img');
    image.draggable = false;
    const [width, height] = model.get('size');
    image.width = width;
    image.height = height;
    const caption = document.createElement('div');
    caption.className = 'rk-camera';
    root.append(strip, image, caption);
    el.append(root);
    let waiting = null;
    const post = event => new Promise(resolve => {
      waiting = {seq: event.seq, resolve};
      model.send(event);
      setTimeout(resolve, 1000);
    });
    const {send} = sender(post);
    attach(image, send, () => height / (image.clientHeight || height));
    bar(strip, model.get('choices'), model.get('current'), send);
    let url = null;
    model.on('msg:custom', (msg, buffers) => {
      if (msg.kind !== 'frame') return;
      const next = URL.createObjectURL(new Blob([buffers[0]], {type: msg.mime}));
      image.src = next;
      if (url) URL.revokeObjectURL(url);
      url = next;
      caption.textContent = 'rasterkit render ' + msg.camera.command.join(' ') + (msg.error ? '  ' + msg.error : '');
      if (waiting && msg.seq >= waiting.seq) { waiting.resolve(); waiting = null; }
    });
    model.send({kind: 'hello'});
    return () => { if (url) URL.revokeObjectURL(url); };
  }
};
