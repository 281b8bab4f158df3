// index.js - refractd's start page: the scenes (GET /v1/scenes), each a link to its
// viewer (/viewer/{id}), with a small preview rendered by refractd.
//
// Previews are ordinary renders (POST /v1/scenes/{id}/render, small, draft settings),
// one at a time and only for cards on screen, so a long list never floods the GPU queue
// in front of the people watching live views.
'use strict';

(function () {
  const THUMB = { width: 240, height: 180, format: 'jpeg', jpeg_quality: 82,
                  stepper: 'euler', step: 2 };
  const $ = (id) => document.getElementById(id);

  async function getJSON(path) {
    const res = await window.refractAuth.fetch(path);
    const json = await res.json().catch(() => null);
    if (!res.ok) throw new Error(json && json.error ? json.error.message : `HTTP ${res.status}`);
    return json;
  }

  function message(text, isError) {
    const m = $('message');
    m.hidden = false;
    m.textContent = text;
    m.classList.toggle('error', !!isError);
  }

  // ---- previews, one at a time --------------------------------------------------------

  const queue = [];
  let rendering = false;

  async function renderNext() {
    if (rendering || queue.length === 0) return;
    rendering = true;
    const { id, box } = queue.shift();
    try {
      const res = await window.refractAuth.fetch(`/v1/scenes/${encodeURIComponent(id)}/render`, {
        method: 'POST',
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify(THUMB),
      });
      if (!res.ok) throw new Error(`HTTP ${res.status}`);
      const url = URL.createObjectURL(await res.blob());
      const img = document.createElement('img');
      img.className = 'thumb';
      img.alt = '';
      img.src = url;
      box.replaceWith(img);
    } catch (err) {
      box.textContent = 'no preview';
    }
    rendering = false;
    renderNext();
  }

  const seen = 'IntersectionObserver' in window
    ? new IntersectionObserver((entries, obs) => {
      for (const e of entries) {
        if (!e.isIntersecting) continue;
        obs.unobserve(e.target);
        queue.push({ id: e.target.dataset.scene, box: e.target });
        renderNext();
      }
    }, { rootMargin: '100px' })
    : null;

  // ---- the cards ----------------------------------------------------------------------

  function card(scene) {
    const li = document.createElement('li');
    li.className = 'scene-card';
    const a = document.createElement('a');
    a.href = `/viewer/${encodeURIComponent(scene.id)}`;
    const box = document.createElement('div');
    box.className = 'thumb thumb-wait';
    box.dataset.scene = scene.id;
    box.textContent = 'preview…';
    const body = document.createElement('div');
    body.className = 'card-body';
    const title = document.createElement('div');
    title.className = 'card-title';
    const name = document.createElement('strong');
    name.textContent = scene.name || scene.id;
    const meta = document.createElement('span');
    meta.className = 'card-meta';
    meta.textContent = `${scene.objects} object${scene.objects === 1 ? '' : 's'}`;
    title.append(name, meta);
    const idLine = document.createElement('div');
    idLine.className = 'card-meta';
    idLine.textContent = scene.id;
    const desc = document.createElement('p');
    desc.className = 'card-desc';
    body.append(title, idLine, desc);
    a.append(box, body);
    li.append(a);
    // The description lives in the document (GET /v1/scenes/{id}); fetched in passing.
    getJSON(`/v1/scenes/${encodeURIComponent(scene.id)}`)
      .then((s) => {
        const d = s.document && s.document.description;
        if (d) { desc.textContent = d; a.title = d; }
      })
      .catch(() => {});
    if (seen) seen.observe(box); else { queue.push({ id: scene.id, box }); renderNext(); }
    return li;
  }

  async function main() {
    getJSON('/v1/health')
      .then((h) => { $('renderer').textContent = h.gpu ? h.gpu.renderer : ''; })
      .catch(() => {});
    try {
      const list = await getJSON('/v1/scenes');
      const scenes = list.scenes || [];
      if (scenes.length === 0) {
        message('refractd has no scenes yet. Create one with POST /v1/scenes (docs/api.md), ' +
                'or start refractd with --scene-dir proto/examples.');
        return;
      }
      $('scene-list').replaceChildren(...scenes.map(card));
    } catch (err) {
      message(`Cannot list the scenes: ${err.message}`, true);
    }
  }

  main();
})();
