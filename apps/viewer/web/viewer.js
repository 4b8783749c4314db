// The page's main loop: reads the server's update stream (GET /stream, one long chunked
// response; the page never sends anything else), applies its messages to the streams, updates
// the scene and the panel, and reconnects after a drop (the server then sends everything again).
// window.ldsmViewer.counts tells what has arrived (the browser test reads it); the title repeats
// it.
'use strict';

(() => {
  const P = LdsmProtocol;
  const streams = {
    [P.KIND_TRAJECTORY]: new P.Stream(7),
    [P.KIND_KEYFRAMES]: new P.Stream(7),
    [P.KIND_POINTS]: new P.Stream(4),
  };
  const counts = { poses: 0, keyframes: 0, points: 0, images: 0, figures: 0, messages: 0,
    rejected: 0, frames: 0, finished: false, connected: false, drawn: 0, errors: 0 };
  window.ldsmViewer = { counts };
  const scene = new LdsmScene(document.getElementById('view'));
  const panel = new LdsmPanel();
  let dirty = { trajectory: false, keyframes: false, points: false };
  let figures = null;
  let figuresNew = false;
  let pendingImage = null;
  let fitPending = false;  // the run is over: show all of it once

  document.getElementById('follow').addEventListener('change', (e) => {
    scene.follow = e.target.checked;
    scene.lastFollowed = null;
  });
  document.getElementById('show-points').addEventListener('change', (e) => {
    scene.points.visible = e.target.checked;
  });

  function onArray(m) {
    const s = streams[m.kind];
    if (!s || !s.apply(m.from, m.floats, m.total)) { ++counts.rejected; return; }
    counts.poses = streams[P.KIND_TRAJECTORY].length;
    counts.keyframes = streams[P.KIND_KEYFRAMES].length;
    counts.points = streams[P.KIND_POINTS].length;
    if (m.kind === P.KIND_TRAJECTORY) dirty.trajectory = true;
    if (m.kind === P.KIND_KEYFRAMES) dirty.keyframes = true;
    if (m.kind === P.KIND_POINTS) dirty.points = true;
  }

  function onFigures(f) {
    if (f.type !== 'figures') return;
    if (f.finished && !counts.finished) fitPending = true;
    figures = f;
    figuresNew = true;
    ++counts.figures;
    counts.frames = f.frames;
    counts.finished = f.finished;
    if (f.finished) panel.setConnection('done');
    dirty.keyframes = true;  // reactivated keyframes and loop edges may have changed
  }

  function onMessage(buffer) {
    ++counts.messages;
    const m = P.decodeMessage(buffer);
    if (!m) ++counts.rejected;
    else if (m.kind === P.KIND_FIGURES) onFigures(m.figures);
    else if (m.kind === P.KIND_IMAGE) { pendingImage = m.image; ++counts.images; }
    else onArray(m);
  }

  async function readStream() {
    const response = await fetch('stream', { cache: 'no-store' });
    if (!response.ok || !response.body) return;  // e.g. 503: too many pages open
    for (const s of Object.values(streams)) s.reset();
    counts.connected = true;
    panel.setConnection('on');
    const reader = response.body.getReader();
    const records = new P.RecordReader();
    try {
      for (;;) {
        const { done, value } = await reader.read();
        if (done) return;
        for (const message of records.push(value)) onMessage(message);
      }
    } finally {
      reader.cancel().catch(() => {});
    }
  }

  async function connect() {
    try {
      await readStream();
    } catch (e) {
      console.warn('ldsm viewer: stream ended:', e.message);
    }
    counts.connected = false;
    panel.setConnection(counts.finished ? 'done' : 'off');
    setTimeout(connect, counts.finished ? 10000 : 2000);
  }

  function frame() {
    try {
      draw();
    } catch (e) {
      ++counts.errors;  // the test reads it; the page keeps going
      console.error(e);
    }
    requestAnimationFrame(frame);
  }

  function draw() {
    const traj = streams[P.KIND_TRAJECTORY], kfs = streams[P.KIND_KEYFRAMES];
    const pts = streams[P.KIND_POINTS];
    if (dirty.trajectory) scene.updateTrajectory(traj);
    if (dirty.keyframes || dirty.trajectory) {
      scene.updateKeyframes(kfs, figures ? figures.reactivated : []);
      scene.updateLoops(kfs, figures ? figures.loop_edges : []);
    }
    if (dirty.points) scene.updatePoints(pts);
    let fitted = false;
    if (fitPending && traj.length > 0) {
      fitted = true;
      scene.root.updateMatrixWorld();
      scene.fitAll(traj);
      scene.follow = false;
      document.getElementById('follow').checked = false;
      fitPending = false;
    }
    if (figures) scene.updateCurrent(figures.current);
    if (figuresNew) {
      panel.showFigures(figures, counts);
      document.title = `ldsm viewer · ${counts.poses} poses · ${counts.points} points`;
      figuresNew = false;
    }
    if (pendingImage) { panel.showImage(pendingImage); pendingImage = null; }
    const changed = dirty.trajectory || dirty.keyframes || dirty.points || fitted;
    dirty = { trajectory: false, keyframes: false, points: false };
    if (scene.render(changed) && traj.length > 0) ++counts.drawn;
  }

  connect();
  requestAnimationFrame(frame);
})();
