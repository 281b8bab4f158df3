// viewer.js - refractd's web viewer (docs/views.md, "The web viewer").
//
// The page at /viewer/{scene} opens a view session (POST /v1/scenes/{scene}/views, with an
// image size that fits the window) or attaches to one (?view=VID), shows the frames of
// the session's MJPEG stream in an <img> (read by mjpeg.js, which says why), and turns the mouse into camera changes (PATCH
// /v1/views/{vid}): drag orbits around look_at, the wheel moves the eye along the view
// direction, shift-drag or right-drag pans. The first light's direction is set with
// PUT /v1/scenes/{scene}/lights/{name}. The status line shows what the view status
// (polled about once a second) and the scene's events (Server-Sent Events) say: the
// renderer, the frame's render time, the frame rate and the irradiance state.
//
// Requests that change something are coalesced: at most one PATCH (and one light PUT) is
// in flight, and changes made meanwhile are merged and sent as one when it returns, so a
// fast mouse never builds a queue in front of a slow renderer.
//
// Plain JavaScript, no framework, no build step; everything comes from refractd.
'use strict';

(function () {
  // ---- settings ------------------------------------------------------------------------

  // URL options: ?view=VID attaches to a session; ?size=WxH fixes the image size;
  // ?quality=draft|normal|final starts with that preset (slow machines: draft).
  const MAX_WIDTH = 960;        // image size cap (pixels); ?size=WxH overrides
  const MAX_HEIGHT = 720;
  const MIN_SIDE = 64;
  const POLL_MS = 1000;         // view status
  const FPS_WINDOW_MS = 3000;   // frame rate over this window
  const ORBIT_RAD_PER_PX = 0.008;
  const ZOOM_PER_PX = 0.0015;   // wheel: distance *= exp(deltaY * this)
  const POLAR_MIN = 0.02;       // radians from the up axis: never flip over the pole
  const KEY_ORBIT_PX = 24;      // arrow keys act like a drag of this many pixels

  // ---- small helpers -------------------------------------------------------------------

  const $ = (id) => document.getElementById(id);
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]];
  const length = (a) => Math.sqrt(dot(a, a));
  const normalize = (a) => { const l = length(a); return l > 0 ? scale(a, 1 / l) : a; };
  const clamp = (x, lo, hi) => Math.min(hi, Math.max(lo, x));
  const deg = (r) => r * 180 / Math.PI;
  const rad = (d) => d * Math.PI / 180;
  const round6 = (v) => v.map((x) => Math.round(x * 1e6) / 1e6);

  // An error answer of API v1 is {"error": {"code", "message"}}; anything else (a proxy's
  // HTML, a dropped connection) becomes an Error with what we know.
  async function api(method, path, body, options) {
    const init = Object.assign({ method, headers: {} }, options || {});
    if (body !== undefined) {
      init.headers['Content-Type'] = 'application/json';
      init.body = JSON.stringify(body);
    }
    const res = await window.refractAuth.fetch(path, init);
    if (res.status === 204) return { status: 204, json: null };
    const text = await res.text();
    let json = null;
    try { json = text ? JSON.parse(text) : null; } catch (e) { json = null; }
    if (!res.ok) {
      const err = new Error(json && json.error ? json.error.message
                                                : `${method} ${path}: HTTP ${res.status}`);
      err.status = res.status;
      err.code = json && json.error ? json.error.code : 'http_' + res.status;
      throw err;
    }
    return { status: res.status, json };
  }

  // Sends merged bodies one at a time: push() merges its fields into what is waiting;
  // when nothing is in flight the merge is sent at once. send(body) returns a promise.
  class Coalescer {
    constructor(send, onAnswer, onError) {
      this.send = send;
      this.onAnswer = onAnswer;
      this.onError = onError;
      this.pending = null;
      this.inflight = false;
    }
    push(fields) {
      this.pending = Object.assign(this.pending || {}, fields);
      if (!this.inflight) this.flush();
    }
    replace(body) { // for bodies that are whole documents, not fields to merge
      this.pending = null;
      this.push(body);
    }
    async flush() {
      while (this.pending) {
        const body = this.pending;
        this.pending = null;
        this.inflight = true;
        try {
          this.onAnswer(await this.send(body));
        } catch (err) {
          this.onError(err);
        }
        this.inflight = false;
      }
    }
  }

  // ---- state ---------------------------------------------------------------------------

  const sceneId = decodeURIComponent(location.pathname.replace(/^\/viewer\//, '').split('/')[0]);
  const query = new URLSearchParams(location.search);

  const state = {
    scene: sceneId,
    view: null,          // the session id
    ownView: false,      // created here (deleted on pagehide) rather than attached to
    status: null,        // the newest view status
    camera: null,        // the camera as this page wants it (sent or about to be)
    homeCamera: null,    // for "Reset view"
    light: null,         // the first light, as GET /v1/scenes/{id}/lights gave it
    lightCenter: [0, 0, 0],
    irradiance: { state: null, progress: null }, // from the events
    frameTimes: [],      // when each frame was shown (ms), for the frame rate
    shown: null,         // the frame on screen: {seq, kind, renderMs, irradiance, width, height}
    stream: null,        // AbortController of the stream being read
    firstFrame: false,
    ended: false,
    renderer: null,
    timers: [],
    events: null,
  };
  window.refractViewer = state; // for the browser test and for curious people

  const img = $('frame');
  const stage = $('stage');

  // ---- the overlay and the connection pill -------------------------------------------

  function overlay(text, isError, action) {
    const box = $('overlay');
    box.hidden = false;
    box.classList.toggle('error', !!isError);
    box.replaceChildren();
    const inner = document.createElement('div');
    if (!isError) {
      const spin = document.createElement('div');
      spin.className = 'spinner';
      inner.append(spin);
    }
    const p = document.createElement('div');
    p.textContent = text;
    inner.append(p);
    if (action) {
      const b = document.createElement('button');
      b.type = 'button';
      b.textContent = action.label;
      b.addEventListener('click', action.run);
      inner.append(b);
    }
    box.append(inner);
  }

  function hideOverlay() { $('overlay').hidden = true; }

  function setConn(text, kind) {
    const pill = $('conn');
    pill.textContent = text;
    pill.dataset.state = kind;
  }

  // ---- image size ---------------------------------------------------------------------

  // The session's image size: the stage's size in CSS pixels, capped, a multiple of 4 (so
  // a half-size preview frame has whole pixels).
  function wantedSize() {
    const forced = /^(\d+)x(\d+)$/.exec(query.get('size') || '');
    if (forced) return { width: +forced[1], height: +forced[2] };
    const r = stage.getBoundingClientRect();
    const fit = (v, cap) => Math.max(MIN_SIDE, Math.floor(Math.min(v, cap) / 4) * 4);
    return { width: fit(r.width - 16, MAX_WIDTH), height: fit(r.height - 16, MAX_HEIGHT) };
  }

  function showSize(width, height) {
    img.style.width = width + 'px';
    img.style.height = height + 'px';
  }

  // ---- the session --------------------------------------------------------------------

  async function start() {
    overlay('Starting the view…');
    setConn('connecting', 'connecting');
    try {
      loadHealth();
      const attach = query.get('view');
      let status = null;
      if (attach) {
        try {
          status = (await api('GET', `/v1/views/${encodeURIComponent(attach)}`)).json;
        } catch (err) {
          if (err.status !== 404) throw err;
          status = null; // gone: start our own below
        }
      }
      if (status === null) {
        const body = wantedSize();
        if (query.get('quality')) body.quality = query.get('quality');
        status = (await api('POST', `/v1/scenes/${encodeURIComponent(sceneId)}/views`, body)).json;
        state.ownView = true;
      }
      state.view = status.id;
      state.camera = JSON.parse(JSON.stringify(status.camera));
      state.homeCamera = JSON.parse(JSON.stringify(status.camera));
      onStatus(status);
      syncControls(status);
      openStream(status);
      state.timers.push(setInterval(poll, POLL_MS));
      loadLights();
      listenEvents();
    } catch (err) {
      setConn('error', 'error');
      overlay(`Could not open a view of “${sceneId}”: ${err.message}`, true,
              { label: 'Try again', run: () => location.reload() });
    }
  }

  // Reads the session's stream (mjpeg.js) and shows each frame in the <img>. Only the
  // newest frame waits for the <img>: one that arrives while another is being decoded
  // replaces the waiting one, so a slow page never builds a queue.
  function openStream(status) {
    if (state.stream) state.stream.abort();
    const stream = new AbortController();
    state.stream = stream;
    state.firstFrame = false;
    showSize(status.width, status.height);
    RefractMjpeg.read(status.stream, { signal: stream.signal, onFrame: showFrame })
      .then(() => streamEnded(stream, null), (err) => streamEnded(stream, err));
  }

  function streamEnded(stream, err) {
    if (stream.signal.aborted || state.ended || !state.view) return;
    // The session expired or was deleted, or refractd stopped.
    setConn('stream ended', 'error');
    overlay(`The frame stream ended${err ? `: ${err.message}` : '.'}`, true,
            { label: 'Reconnect', run: reconnect });
  }

  let waiting = null;   // the newest frame not yet handed to the <img>
  let decoding = false;
  let shownUrl = null;

  function showFrame(frame) {
    // The keep-alive resends the frame on screen: nothing to draw.
    if (state.shown && frame.seq === state.shown.seq && !waiting) return;
    waiting = frame;
    if (!decoding) drawNext();
  }

  function drawNext() {
    const frame = waiting;
    waiting = null;
    if (!frame) return;
    decoding = true;
    const url = URL.createObjectURL(frame.blob);
    const done = (ok) => {
      decoding = false;
      if (ok) {
        if (shownUrl) URL.revokeObjectURL(shownUrl);
        shownUrl = url;
        onShown(frame);
      } else {
        URL.revokeObjectURL(url);
      }
      drawNext();
    };
    img.onload = () => done(true);
    img.onerror = () => done(false); // a part that is not a JPEG: keep the last good one
    img.src = url;
    img.hidden = false;
  }

  function onShown(frame) {
    const now = performance.now();
    state.shown = { seq: frame.seq, kind: frame.kind, renderMs: frame.renderMs,
                    irradiance: frame.irradiance, width: img.naturalWidth, height: img.naturalHeight };
    state.frameTimes.push(now);
    while (state.frameTimes.length > 0 && now - state.frameTimes[0] > FPS_WINDOW_MS)
      state.frameTimes.shift();
    if (!state.firstFrame) {
      state.firstFrame = true;
      hideOverlay();
      setConn('live', 'live');
    }
    renderStatus();
  }

  async function reconnect() {
    try {
      const status = (await api('GET', `/v1/views/${state.view}`)).json;
      onStatus(status);
      openStream(status);
    } catch (err) {
      if (err.status === 404 && state.ownView) {
        stopSession();
        state.view = null;
        start();
      } else {
        overlay(`Cannot reconnect: ${err.message}`, true, { label: 'Reload', run: () => location.reload() });
      }
    }
  }

  // Stops polling and reading the stream (the session is gone, or the page goes).
  function stopSession() {
    state.timers.forEach(clearInterval);
    state.timers = [];
    if (state.stream) state.stream.abort();
    state.stream = null;
  }

  async function poll() {
    if (!state.view || state.ended || document.hidden) return;
    try {
      onStatus((await api('GET', `/v1/views/${state.view}`)).json);
    } catch (err) {
      if (err.status === 404) {
        stopSession();
        setConn('session ended', 'error');
        overlay('This view session has ended (idle too long, or deleted).', true,
                { label: 'Start a new view', run: reconnect });
      } else {
        setConn('offline', 'error');
      }
    }
  }

  async function loadHealth() {
    try {
      const h = (await api('GET', '/v1/health')).json;
      if (!state.renderer && h && h.gpu) {
        state.renderer = h.gpu.renderer;
        renderStatus();
      }
    } catch (err) {
      // The view status carries the renderer too; health is only a head start.
    }
  }

  // ---- view status -> the page --------------------------------------------------------

  function onStatus(status) {
    if (!status || !status.id) return;
    state.status = status;
    if (status.renderer) state.renderer = status.renderer;
    if (state.firstFrame) {
      setConn(status.state === 'rendering' ? 'rendering' : 'live',
              status.state === 'rendering' ? 'rendering' : 'live');
    }
    renderStatus();
  }

  // Frames shown per second over the last few seconds (0 while nothing changes: refractd
  // sends a frame only when something visible changed).
  function fps() {
    const now = performance.now();
    const recent = state.frameTimes.filter((t) => now - t <= FPS_WINDOW_MS);
    return recent.length / (FPS_WINDOW_MS / 1000);
  }

  function irradianceText() {
    const f = state.status && state.status.frame;
    const frameIrr = state.shown && state.shown.irradiance ? state.shown.irradiance
                                                           : f ? f.irradiance : null;
    const ev = state.irradiance;
    if (ev.state === 'computing' || ev.state === 'queued') {
      const pct = ev.progress != null ? ` ${Math.round(ev.progress * 100)} %` : '';
      return { key: 'computing', text: `computing${pct}` + (frameIrr ? ` (frame: ${frameIrr})` : '') };
    }
    if (ev.state === 'failed') return { key: 'failed', text: 'failed' };
    return { key: frameIrr || 'unknown', text: frameIrr || '–' };
  }

  function renderStatus() {
    const st = state.status;
    const f = st && st.frame;
    $('s-renderer').textContent = state.renderer || 'renderer …';
    $('s-renderer').title = state.renderer ? `GPU: ${state.renderer}` : '';
    // The frame on screen, as its part's headers described it.
    const sh = state.shown;
    if (sh) {
      $('s-frame').textContent = `frame ${sh.seq} · ${sh.width}×${sh.height} ${sh.kind || ''}`.trim();
      if (sh.renderMs != null) {
        $('s-render').textContent = `render ${sh.renderMs.toFixed(1)} ms`;
        $('f-render').textContent = `${sh.renderMs.toFixed(1)} ms`;
      }
      $('f-seq').textContent = `${sh.seq}${sh.kind ? ` (${sh.kind})` : ''}`;
    }
    if (f) {
      $('f-encode').textContent = `${f.encode_ms.toFixed(1)} ms · ${(f.bytes / 1024).toFixed(0)} KiB`;
    }
    const rate = fps();
    $('s-fps').textContent = `${rate.toFixed(1)} fps`;
    $('f-fps').textContent = `${rate.toFixed(1)} fps` + (st && st.max_fps ? ` (max ${st.max_fps})` : '');
    if (st) {
      $('f-size').textContent = `${st.width}×${st.height}`;
      $('f-view').textContent = `${st.id}${st.streams != null ? ` · ${st.streams} stream${st.streams === 1 ? '' : 's'}` : ''}`;
    }
    const irr = irradianceText();
    $('s-irr').textContent = `irradiance ${irr.text}`;
    $('irr-light').textContent = irr.text;
    $('irr-light').dataset.state = irr.key;
    const bar = $('irr-progress');
    const ev = state.irradiance;
    bar.hidden = !(ev.state === 'computing' && ev.progress != null);
    if (!bar.hidden) bar.firstElementChild.style.width = `${Math.round(ev.progress * 100)}%`;
  }

  // Sets the controls from a status (once, at start, and after an attach).
  function syncControls(status) {
    const ev = status.exposure || 0;
    $('exposure').value = ev;
    $('exposure-out').textContent = `${ev >= 0 ? '+' : ''}${Number(ev).toFixed(1)} EV`;
    if (status.tonemap) $('tonemap').value = status.tonemap;
    if (status.quality) $('quality').value = status.quality;
    $('scene-name').textContent = status.scene || sceneId;
    document.title = `${status.scene || sceneId} · Refract viewer`;
  }

  // ---- PATCH /v1/views/{vid}, coalesced ------------------------------------------------

  const patcher = new Coalescer(
    (body) => api('PATCH', `/v1/views/${state.view}`, body).then((r) => r.json),
    (status) => onStatus(status),
    (err) => showError(err));

  // A failed change: refractd's message (it says what was wrong) for a few seconds.
  let toastTimer = 0;
  function showError(err) {
    const t = $('toast');
    t.textContent = err.message;
    t.hidden = false;
    clearTimeout(toastTimer);
    toastTimer = setTimeout(() => { t.hidden = true; }, 8000);
    console.warn('refract viewer:', err.message);
  }

  function sendCamera() {
    const c = state.camera;
    patcher.push({ camera: { eye: round6(c.eye), look_at: round6(c.look_at), up: round6(c.up) } });
  }

  // ---- camera motion ------------------------------------------------------------------

  // Orbit around look_at: dx turns about the up axis, dy changes the angle from the up
  // axis (clamped short of the poles). Dragging right turns the object right.
  function orbit(dx, dy) {
    const c = state.camera;
    const up = normalize(c.up);
    const off = sub(c.eye, c.look_at);
    const r = length(off);
    if (r === 0) return;
    let horiz = sub(off, scale(up, dot(off, up)));
    if (length(horiz) < 1e-9 * r) horiz = cross(up, [1, 0, 0]);
    horiz = normalize(horiz);
    const side = normalize(cross(up, horiz));
    // Turn about up: rotate the horizontal direction by -dx.
    const yaw = -dx * ORBIT_RAD_PER_PX;
    horiz = add(scale(horiz, Math.cos(yaw)), scale(side, Math.sin(yaw)));
    const polar = Math.acos(clamp(dot(off, up) / r, -1, 1));
    const polarNew = clamp(polar - dy * ORBIT_RAD_PER_PX, POLAR_MIN, Math.PI - POLAR_MIN);
    const dir = add(scale(up, Math.cos(polarNew)), scale(horiz, Math.sin(polarNew)));
    c.eye = add(c.look_at, scale(dir, r));
    sendCamera();
  }

  // Zoom: the eye moves along the view direction; distance scales by exp(amount).
  function zoom(amount) {
    const c = state.camera;
    const off = sub(c.eye, c.look_at);
    const r = length(off);
    if (r === 0) return;
    const rNew = clamp(r * Math.exp(amount), 1e-3, 1e5);
    c.eye = add(c.look_at, scale(off, rNew / r));
    sendCamera();
  }

  // Pan: eye and look_at move together in the image plane, so that the point under the
  // cursor at look_at's depth follows the cursor.
  function pan(dx, dy) {
    const c = state.camera;
    const off = sub(c.eye, c.look_at);
    const r = length(off);
    const fwd = normalize(scale(off, -1));
    const right = normalize(cross(fwd, normalize(c.up)));
    const camUp = cross(right, fwd);
    const fov = rad(c.fov_y_deg || 40);
    const perPx = 2 * r * Math.tan(fov / 2) / Math.max(img.clientHeight, 1);
    const move = add(scale(right, -dx * perPx), scale(camUp, dy * perPx));
    c.eye = add(c.eye, move);
    c.look_at = add(c.look_at, move);
    sendCamera();
  }

  function resetCamera() {
    if (!state.homeCamera) return;
    state.camera = JSON.parse(JSON.stringify(state.homeCamera));
    sendCamera();
  }

  let drag = null;
  stage.addEventListener('pointerdown', (e) => {
    if (!state.camera) return;
    const panning = e.button === 2 || e.button === 1 || e.shiftKey;
    if (e.button !== 0 && !panning) return;
    drag = { x: e.clientX, y: e.clientY, panning, id: e.pointerId };
    stage.setPointerCapture(e.pointerId);
    stage.classList.add(panning ? 'panning' : 'dragging');
  });
  stage.addEventListener('pointermove', (e) => {
    if (!drag || e.pointerId !== drag.id) return;
    const dx = e.clientX - drag.x;
    const dy = e.clientY - drag.y;
    if (dx === 0 && dy === 0) return;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.panning) pan(dx, dy); else orbit(dx, dy);
  });
  const endDrag = (e) => {
    if (!drag || e.pointerId !== drag.id) return;
    drag = null;
    stage.classList.remove('dragging', 'panning');
  };
  stage.addEventListener('pointerup', endDrag);
  stage.addEventListener('pointercancel', endDrag);
  stage.addEventListener('contextmenu', (e) => e.preventDefault());
  stage.addEventListener('dblclick', resetCamera);
  stage.addEventListener('wheel', (e) => {
    if (!state.camera) return;
    e.preventDefault();
    const px = e.deltaMode === 1 ? e.deltaY * 16 : e.deltaMode === 2 ? e.deltaY * 400 : e.deltaY;
    zoom(px * ZOOM_PER_PX);
  }, { passive: false });
  stage.addEventListener('keydown', (e) => {
    if (!state.camera) return;
    const k = KEY_ORBIT_PX;
    const keys = {
      ArrowLeft: () => (e.shiftKey ? pan(-k, 0) : orbit(-k, 0)),
      ArrowRight: () => (e.shiftKey ? pan(k, 0) : orbit(k, 0)),
      ArrowUp: () => (e.shiftKey ? pan(0, -k) : orbit(0, -k)),
      ArrowDown: () => (e.shiftKey ? pan(0, k) : orbit(0, k)),
      '+': () => zoom(-0.1), '=': () => zoom(-0.1), '-': () => zoom(0.1),
      r: resetCamera,
    };
    if (keys[e.key]) {
      keys[e.key]();
      e.preventDefault();
    }
  });
  $('reset').addEventListener('click', resetCamera);

  // The window changed size: the session's image follows (once the resizing settles).
  let resizeTimer = 0;
  window.addEventListener('resize', () => {
    clearTimeout(resizeTimer);
    resizeTimer = setTimeout(() => {
      if (!state.status || query.get('size')) return;
      const size = wantedSize();
      if (size.width !== state.status.width || size.height !== state.status.height) {
        showSize(size.width, size.height);
        patcher.push(size);
      }
    }, 350);
  });

  // ---- exposure, tone mapping, quality -------------------------------------------------

  $('exposure').addEventListener('input', (e) => {
    const ev = Number(e.target.value);
    $('exposure-out').textContent = `${ev >= 0 ? '+' : ''}${ev.toFixed(1)} EV`;
    patcher.push({ exposure: ev });
  });
  $('tonemap').addEventListener('change', (e) => patcher.push({ tonemap: e.target.value }));
  $('quality').addEventListener('change', (e) => patcher.push({ quality: e.target.value }));

  // ---- the light ----------------------------------------------------------------------

  // Azimuth (degrees about +y, 0 = from +z, 90 = from +x) and elevation (degrees above
  // the horizontal plane) of the direction the light comes FROM. Directions in the scene
  // point along propagation, so a directional light's `direction` is minus this vector.
  function fromAngles(azDeg, elDeg) {
    const az = rad(azDeg);
    const el = rad(elDeg);
    return [Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az)];
  }

  function toAngles(v) {
    const u = normalize(v);
    return { az: deg(Math.atan2(u[0], u[2])), el: deg(Math.asin(clamp(u[1], -1, 1))) };
  }

  // Where the light comes from, for each light type: a directional light from -direction;
  // a point or spot light from its position seen from the scene's centre (look_at).
  function lightFrom(light) {
    if (light.type === 'directional') return scale(light.direction, -1);
    return sub(light.position, state.lightCenter);
  }

  function lightWith(light, azDeg, elDeg) {
    const from = fromAngles(azDeg, elDeg);
    const next = JSON.parse(JSON.stringify(light));
    delete next.name; // the URL names it
    if (light.type === 'directional') {
      next.direction = round6(scale(from, -1));
    } else {
      const r = length(sub(light.position, state.lightCenter)) || 1;
      next.position = round6(add(state.lightCenter, scale(from, r)));
      if (light.type === 'spot') next.direction = round6(scale(from, -1)); // aim at the centre
    }
    return next;
  }

  const lightPutter = new Coalescer(
    (body) => api('PUT', `/v1/scenes/${encodeURIComponent(sceneId)}/lights/${encodeURIComponent(state.light.name)}`, body)
      .then((r) => r.json),
    (answer) => onLightAnswer(answer),
    (err) => showError(err));

  // PUT answers with the irradiance status: what this light's volume is doing now.
  function onLightAnswer(answer) {
    const mine = answer && Array.isArray(answer.lights)
      ? answer.lights.find((l) => l.name === state.light.name) : null;
    if (mine) {
      state.irradiance = { state: mine.state, progress: mine.progress != null ? mine.progress : null };
      renderStatus();
    }
  }

  function showAngles(a) {
    $('azimuth-out').textContent = `${Math.round(a.az)}°`;
    $('elevation-out').textContent = `${Math.round(a.el)}°`;
  }

  async function loadLights() {
    if (state.homeCamera) state.lightCenter = state.homeCamera.look_at.slice();
    try {
      const lights = (await api('GET', `/v1/scenes/${encodeURIComponent(sceneId)}/lights`)).json;
      const first = lights && lights.lights && lights.lights[0];
      if (!first) {
        $('light-name').textContent = 'none';
        $('light-note').textContent = 'This scene has no lights: it is lit by its environment only.';
        for (const f of $('light-section').querySelectorAll('.field')) f.hidden = true;
        return;
      }
      state.light = first;
      const a = toAngles(lightFrom(first));
      $('light-name').textContent = `${first.name} · ${first.type}`;
      $('azimuth').value = Math.round(a.az);
      $('elevation').value = Math.round(a.el);
      $('azimuth').disabled = false;
      $('elevation').disabled = false;
      showAngles(a);
      loadIrradiance();
    } catch (err) {
      $('light-note').textContent = `Lights: ${err.message}`;
    }
  }

  async function loadIrradiance() {
    try {
      onLightAnswer((await api('GET', `/v1/scenes/${encodeURIComponent(sceneId)}/irradiance`)).json);
    } catch (err) {
      // Shown from the frames' irradiance state instead.
    }
  }

  function onLightInput() {
    if (!state.light) return;
    const a = { az: Number($('azimuth').value), el: Number($('elevation').value) };
    showAngles(a);
    const body = lightWith(state.light, a.az, a.el);
    state.light = Object.assign({}, body, { name: state.light.name });
    lightPutter.replace(body); // each body is the whole light

  }
  $('azimuth').addEventListener('input', onLightInput);
  $('elevation').addEventListener('input', onLightInput);

  // ---- the scene's events (Server-Sent Events) ----------------------------------------

  function listenEvents() {
    // EventSource, or a fetch reader when a token is needed (auth.js says why).
    const es = window.refractAuth.events(`/v1/scenes/${encodeURIComponent(sceneId)}/events`);
    state.events = es;
    const data = (e) => { try { return JSON.parse(e.data); } catch (err) { return null; } };
    const mine = (d) => d && state.light && d.light === state.light.name;
    es.addEventListener('irradiance.progress', (e) => {
      const d = data(e);
      if (!mine(d)) return;
      state.irradiance = { state: d.state || 'computing', progress: d.progress != null ? d.progress : null };
      renderStatus();
    });
    es.addEventListener('irradiance.ready', (e) => {
      if (!mine(data(e))) return;
      state.irradiance = { state: 'ready', progress: null };
      renderStatus();
    });
    es.addEventListener('irradiance.failed', (e) => {
      if (!mine(data(e))) return;
      state.irradiance = { state: 'failed', progress: null };
      renderStatus();
    });
    es.addEventListener('scene.deleted', () => {
      state.ended = true;
      setConn('scene deleted', 'error');
      overlay('This scene was deleted.', true, { label: 'All scenes', run: () => { location.href = '/'; } });
    });
  }

  // ---- leaving ------------------------------------------------------------------------

  // End the session we made; keepalive lets the request outlive the page.
  window.addEventListener('pagehide', () => {
    if (state.events) state.events.close();
    stopSession();
    if (state.view && state.ownView) {
      window.refractAuth.fetch(`/v1/views/${state.view}`, { method: 'DELETE', keepalive: true }).catch(() => {});
      state.view = null;
    }
  });
  // Back from the back/forward cache: the old session was deleted on pagehide.
  window.addEventListener('pageshow', (e) => {
    if (e.persisted) location.reload();
  });

  $('scene-name').textContent = sceneId;
  start();
})();
