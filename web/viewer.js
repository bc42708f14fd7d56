// manylight view: the page. It draws the frames the server sends (a JSON status, then the RGBA8
// pixels; before them "loading" while the scene loads, then a "hello"), turns the mouse and keys
// into views (eye, target, up), and sends the settings.
'use strict';
(() => {
  const $ = (id) => document.getElementById(id);
  const canvas = $('view');
  const ctx = canvas.getContext('2d');
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const len = (a) => Math.sqrt(dot(a, a));
  const norm = (a) => mul(a, 1 / len(a));
  // Rodrigues: v turned by `angle` about the unit axis k.
  const rotate = (v, k, angle) => {
    const c = Math.cos(angle), s = Math.sin(angle);
    return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
  };

  let view = null, home = null, pending = null, meta = null;
  let frames = 0, movingFrames = 0, lastFrameTime = 0, fps = 0;
  document.body.dataset.frames = '0';
  const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
  const ws = new WebSocket(`${proto}//${location.host}/ws`);
  ws.binaryType = 'arraybuffer';
  const send = (msg) => { if (ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(msg)); };

  // At most one view message per animation frame.
  let viewQueued = false;
  const sendView = () => {
    if (viewQueued) return;
    viewQueued = true;
    requestAnimationFrame(() => {
      viewQueued = false;
      send({ type: 'view', eye: view.eye, target: view.target, up: view.up });
    });
  };

  const settingsFrom = (s) => {
    $('vpls').value = Math.round(Math.log2(Math.max(16, s.vpls)));
    $('vpls-out').textContent = s.vpls;
    $('interleave').value = s.interleave;
    $('filter').value = s.filter; $('filter-out').textContent = s.filter;
    $('exposure').value = s.exposure; $('exposure-out').textContent = s.exposure;
    $('integrator').value = s.integrator;
    $('spp-target').value = s.spp;
    $('refine-set').value = s.set;
  };

  ws.onmessage = (ev) => {
    if (typeof ev.data !== 'string') {
      if (!meta) return;
      const { width, height } = meta;
      if (canvas.width !== width || canvas.height !== height) { canvas.width = width; canvas.height = height; }
      ctx.putImageData(new ImageData(new Uint8ClampedArray(ev.data), width, height), 0, 0);
      const now = performance.now();
      if (lastFrameTime && meta.mode === 'moving') fps = 0.8 * fps + 0.2 * (1000 / (now - lastFrameTime));
      lastFrameTime = now;
      frames += 1;
      if (meta.mode === 'moving') movingFrames += 1;
      $('mode').textContent = meta.mode + (meta.mode === 'moving' ? ' (igi)' : ` (${meta.integrator})`);
      $('frame-ms').textContent = meta.frame_ms.toFixed(1);
      $('fps').textContent = fps ? fps.toFixed(1) : '–';
      $('spp').textContent = `${meta.spp} / ${meta.target_spp}`;
      $('progress').value = meta.progress;
      if (meta.command) $('command').textContent = meta.command;
      document.body.dataset.frames = String(frames);
      document.body.dataset.movingFrames = String(movingFrames);
      document.body.dataset.mode = meta.mode;
      document.body.dataset.frameMs = String(meta.frame_ms);
      meta = null;
      return;
    }
    const msg = JSON.parse(ev.data);
    if (msg.type === 'loading') {
      // The server listens while the scene loads; the hello comes once it is ready.
      $('mode').textContent = 'loading the scene';
      $('scene-name').textContent = msg.scene;
      document.body.dataset.mode = 'loading';
    } else if (msg.type === 'hello') {
      $('mode').textContent = 'waiting for the first frame';
      $('error').textContent = '';
      view = msg.view; home = msg.home;
      canvas.width = msg.width; canvas.height = msg.height;
      $('scene-name').textContent = msg.scene;
      const sel = $('integrator');
      sel.replaceChildren(...msg.integrators.map((n) => new Option(n, n)));
      settingsFrom(msg.settings);
    } else if (msg.type === 'frame') {
      meta = msg;
    } else if (msg.type === 'saved') {
      $('saved').textContent = `saved ${msg.path}; to render it again:`;
      $('command').textContent = msg.command;
      document.body.dataset.saved = msg.path;
    } else if (msg.type === 'error') {
      $('error').textContent = msg.message;
    }
  };
  ws.onclose = () => { $('mode').textContent = 'disconnected'; };

  // Mouse: orbit about the target, pan, dolly.
  let drag = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => {
    if (!view) return;
    canvas.setPointerCapture(e.pointerId);
    canvas.focus();
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey };
  });
  canvas.addEventListener('pointerup', () => { drag = null; });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag || !view) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    const offset = sub(view.eye, view.target);
    const dist = len(offset);
    const up = norm(view.up);
    const right = norm(cross(norm(sub(view.target, view.eye)), up));
    if (drag.pan) {
      const move = add(mul(right, -dx * dist * 0.002), mul(up, dy * dist * 0.002));
      view.eye = add(view.eye, move); view.target = add(view.target, move);
    } else {
      let o = rotate(offset, up, -dx * 0.006);
      const r = norm(cross(up, norm(o)));
      const turned = rotate(o, r, dy * 0.006);
      if (Math.abs(dot(norm(turned), up)) < 0.98) o = turned;  // not over the pole
      view.eye = add(view.target, o);
    }
    sendView();
  });
  canvas.addEventListener('wheel', (e) => {
    if (!view) return;
    e.preventDefault();
    const offset = sub(view.eye, view.target);
    const scaled = mul(offset, Math.exp(e.deltaY * 0.001));
    if (len(scaled) > 1e-3) { view.eye = add(view.target, scaled); sendView(); }
  }, { passive: false });
  // Fly: the eye and the target move together.
  canvas.addEventListener('keydown', (e) => {
    if (!view) return;
    const fwd = norm(sub(view.target, view.eye));
    const up = norm(view.up);
    const right = norm(cross(fwd, up));
    const step = len(sub(view.target, view.eye)) * 0.05;
    const dirs = { w: fwd, s: mul(fwd, -1), d: right, a: mul(right, -1), e: up, q: mul(up, -1) };
    const d = dirs[e.key.toLowerCase()];
    if (!d) return;
    const move = mul(d, step);
    view.eye = add(view.eye, move); view.target = add(view.target, move);
    sendView();
  });

  // Settings.
  const sendSettings = () => {
    const vpls = 2 ** Number($('vpls').value);
    $('vpls-out').textContent = vpls;
    $('filter-out').textContent = $('filter').value;
    send({
      type: 'settings', vpls, interleave: $('interleave').value, filter: Number($('filter').value),
      integrator: $('integrator').value, spp: Math.max(1, Number($('spp-target').value) | 0),
      set: $('refine-set').value,
    });
  };
  for (const id of ['vpls', 'interleave', 'filter', 'integrator', 'spp-target', 'refine-set'])
    $(id).addEventListener('change', sendSettings);
  for (const id of ['vpls', 'filter']) $(id).addEventListener('input', () => {
    $('vpls-out').textContent = 2 ** Number($('vpls').value);
    $('filter-out').textContent = $('filter').value;
  });
  $('exposure').addEventListener('input', () => {
    $('exposure-out').textContent = $('exposure').value;
    send({ type: 'settings', exposure: Number($('exposure').value) });
  });
  $('home').addEventListener('click', () => {
    if (!home) return;
    view = JSON.parse(JSON.stringify(home));
    send({ type: 'reset' });
  });
  $('save').addEventListener('click', () => send({ type: 'save' }));
})();
