// The `rasterkit view` page: frames by long polling (GET frame?after=N answers with the next
// frame as soon as there is one), events by POST (rasterkit/viewer/server.py).
import {attach, bar, sender} from './controls.js';

const canvas = document.getElementById('frame');
const stats = {frames: 0, latencies: [], arrivals: [], number: 0, camera: null, final: false};
window.rasterkitViewer = stats;  // read by the browser test

async function post(event) {
  const answer = await fetch('event', {method: 'POST', headers: {'Content-Type': 'application/json'},
                                      body: JSON.stringify(event)});
  if (!answer.ok) document.getElementById('error').textContent = await answer.text();
}

const {send, sent} = sender(post);

async function frames() {
  for (;;) {
    let answer;
    try {
      answer = await fetch('frame?after=' + stats.number);
    } catch (e) {  // the server has stopped
      document.getElementById('error').textContent = 'the viewer has stopped';
      return;
    }
    if (answer.status !== 200) continue;  // no new frame yet
    const arrived = performance.now();
    const blob = await answer.blob();
    const bitmap = await createImageBitmap(blob);  // decoded off the page's main thread
    canvas.getContext('2d').drawImage(bitmap, 0, 0, canvas.width, canvas.height);
    bitmap.close();
    if (stats.url) URL.revokeObjectURL(stats.url);
    stats.url = URL.createObjectURL(blob);  // the picture's bytes, for the browser test
    const seq = Number(answer.headers.get('X-Event-Seq'));
    if (sent.has(seq)) {
      stats.latencies.push(performance.now() - sent.get(seq));
      stats.arrivals.push(arrived - sent.get(seq));
      for (const key of sent.keys()) if (key <= seq) sent.delete(key);
    }
    stats.number = Number(answer.headers.get('X-Frame-Number'));
    stats.final = answer.headers.get('X-Frame-Final') === '1';
    stats.camera = JSON.parse(answer.headers.get('X-Camera'));
    stats.frames += 1;
    document.getElementById('camera').textContent = 'rasterkit render ' + stats.camera.command.join(' ');
    document.getElementById('error').textContent = answer.headers.get('X-Error') || '';
  }
}

const state = await (await fetch('state')).json();
document.getElementById('model').textContent = state.model;
canvas.width = state.size[0];
canvas.height = state.size[1];
attach(canvas, send, () => state.size[1] / (canvas.clientHeight || state.size[1]));
bar(document.getElementById('bar'), state.choices, state.current, send);
frames();
