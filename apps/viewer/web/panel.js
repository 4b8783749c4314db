// The side panel: connection state, the current image with its tracked points, and the live
// figures (frame rate, tracking status, pose latency, drops, keyframes, loops, memory).
'use strict';

class LdsmPanel {
  constructor() {
    this.connection = document.getElementById('connection');
    this.source = document.getElementById('source');
    this.canvas = document.getElementById('image');
    this.table = document.getElementById('figures');
  }

  setConnection(state) {
    const text = { on: 'live', off: 'disconnected', done: 'run finished' }[state] || state;
    this.connection.textContent = text;
    this.connection.className = state;
  }

  showImage(image) {
    if (image.width === 0 || image.height === 0) return;
    const c = this.canvas;
    if (c.width !== image.width || c.height !== image.height) {
      c.width = image.width;
      c.height = image.height;
    }
    const ctx = c.getContext('2d');
    const rgba = ctx.createImageData(image.width, image.height);
    for (let i = 0; i < image.pixels.length; ++i) {
      const v = image.pixels[i];
      rgba.data[4 * i] = rgba.data[4 * i + 1] = rgba.data[4 * i + 2] = v;
      rgba.data[4 * i + 3] = 255;
    }
    ctx.putImageData(rgba, 0, 0);
    ctx.fillStyle = 'rgba(102, 255, 102, 0.85)';
    for (let i = 0; i + 1 < image.points.length; i += 2)
      ctx.fillRect(image.points[i] - 0.75, image.points[i + 1] - 0.75, 1.5, 1.5);
  }

  showFigures(f, counts) {
    this.source.textContent = `${f.mode}: ${f.source}`;
    const rows = [
      ['status', f.status],
      ['frame rate', `${f.fps.toFixed(1)} Hz`],
      ['frames (tracked)', `${f.frames} (${f.tracked_frames})`],
      ['dropped', `${f.dropped_frames}`],
      ['pose latency mean / p99', `${f.latency_mean_ms.toFixed(1)} / ${f.latency_p99_ms.toFixed(1)} ms`],
      ['ms per frame', f.ms_per_frame.toFixed(1)],
      ['keyframes', `${f.keyframes}`],
      ['loops closed', `${f.loops}`],
      ['reactivated keyframes', `${f.reactivations}`],
      ['map points', `${f.map_points}`],
      ['memory (map)', `${f.rss_mb.toFixed(0)} MB (${f.map_mb.toFixed(1)} MB)`],
      ['received poses / points', `${counts.poses} / ${counts.points}`],
    ];
    this.table.replaceChildren(...rows.map(([k, v]) => {
      const tr = document.createElement('tr');
      const a = document.createElement('td'), b = document.createElement('td');
      a.textContent = k;
      b.textContent = v;
      tr.append(a, b);
      return tr;
    }));
  }
}
