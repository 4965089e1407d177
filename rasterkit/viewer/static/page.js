// The `rasterkit view` page: events up and frames down on one WebSocket (rasterkit/viewer/server.py
// describes its messages). The page asks for the next frame only once it has shown the last,
// so only the newest frame comes when the page or the connection is slower than the frames.
import {attach, bar, sender} from './controls.js';

const canvas = document.getElementById('frame');
const stats = {frames: 0, latencies: [], arrivals: [], number: 0, camera: null, final: false};
window.rasterkitViewer = stats;  // read by the browser test
const error = text => { document.getElementById('error').textContent = text; };

const socket = new WebSocket(`ws://${location.host}/socket`);
socket.binaryType = 'arraybuffer';
const opened = new Promise(resolve => socket.addEventListener('open', resolve));
const {send, sent} = sender(async event => { await opened; socket.send(JSON.stringify(event)); });

async function show(buffer) {
  const arrived = performance.now();
  const length = new DataView(buffer).getUint32(0);
  const meta = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
  const blob = new Blob([new Uint8Array(buffer, 4 + length)], {type: meta.mime});
  const bitmap = await createImageBitmap(blob);  // decoded off the page's main thread
  canvas.getContext('2d').drawImage(bitmap, 0, 0, canvas.width, canvas.height);
  bitmap.close();
  if (stats.url) URL.revokeObjectURL(stats.url);
  stats.url = URL.createObjectURL(blob);  // the picture's bytes, for the browser test
  if (sent.has(meta.seq)) {
    stats.latencies.push(performance.now() - sent.get(meta.seq));
    stats.arrivals.push(arrived - sent.get(meta.seq));
    for (const key of sent.keys()) if (key <= meta.seq) sent.delete(key);
  }
  stats.number = meta.number;
  stats.final = meta.final;
  stats.camera = meta.camera;
  stats.frames += 1;
  document.getElementById('camera').textContent = 'rasterkit render ' + meta.camera.command.join(' ');
  error(meta.error);
}

socket.addEventListener('message', async message => {
  if (typeof message.data === 'string') {  // a bad event's answer
    error(JSON.parse(message.data).error);
    return;
  }
  try {
    await show(message.data);
  } finally {  // a frame that cannot be shown stops none after it
    socket.send(JSON.stringify({ready: stats.number}));
  }
});
socket.addEventListener('close', () => error('the viewer has stopped'));

const state = await (await fetch('state')).json();
document.getElementById('model').textContent = state.model;
canvas.width = state.size[0];
canvas.height = state.size[1];
attach(canvas, send, () => state.size[1] / (canvas.clientHeight || state.size[1]));
bar(document.getElementById('bar'), state.choices, state.current, send);
await opened;
socket.send(JSON.stringify({ready: 0}));
