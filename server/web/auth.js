// auth.js - the bearer token of a refractd started with --token-file, for the viewer's
// pages (docs/api.md "Security").
//
// refractd serves the pages without a token; the API answers 401 `unauthorized` until the
// request carries "Authorization: Bearer TOKEN". On the first 401 the page asks for the
// token once (a prompt), keeps it in this tab's sessionStorage (gone when the tab
// closes; never in a URL, a cookie or localStorage) and sends it as that header.
// EventSource cannot send headers, so with a token the event stream is read with fetch
// (refractAuth.events); without one the browser's EventSource does it.
'use strict';

(function () {
  const KEY = 'refract.token';

  function token() {
    try { return sessionStorage.getItem(KEY) || ''; } catch (e) { return ''; }
  }

  function remember(t) {
    try { sessionStorage.setItem(KEY, t); } catch (e) { /* private mode: this page only */ }
    memo = t;
  }

  let memo = '';
  const current = () => token() || memo;

  function headers(extra) {
    const h = Object.assign({}, extra || {});
    const t = current();
    if (t) h.Authorization = 'Bearer ' + t;
    return h;
  }

  // fetch() with the token; on 401 asks for it (once for all requests waiting: prompt()
  // blocks the page, so a request that finds a new token after its 401 just retries).
  async function authFetch(url, init) {
    const opts = Object.assign({}, init || {});
    for (let attempt = 0; attempt < 3; attempt++) {
      const used = current();
      opts.headers = headers(init && init.headers);
      const res = await fetch(url, opts);
      if (res.status !== 401) return res;
      if (current() !== used) continue; // another request already asked
      const given = window.prompt(used
        ? 'refractd did not accept that token. Its access token (the first line of its --token-file):'
        : 'This refractd needs its access token (the first line of its --token-file):');
      if (!given || !given.trim()) return res;
      remember(given.trim());
    }
    return fetch(url, Object.assign({}, opts, { headers: headers(init && init.headers) }));
  }

  // A Server-Sent Events reader over fetch, with the part of EventSource the viewer uses:
  // addEventListener(type, fn) with e.data, close(), and reconnection with Last-Event-ID.
  class FetchEvents {
    constructor(url) {
      this.url = url;
      this.listeners = {};
      this.lastId = null;
      this.abort = new AbortController();
      this.closed = false;
      this.run();
    }

    addEventListener(type, fn) {
      (this.listeners[type] = this.listeners[type] || []).push(fn);
    }

    close() {
      this.closed = true;
      this.abort.abort();
    }

    dispatch(type, data) {
      for (const fn of this.listeners[type] || []) {
        try { fn({ type, data, lastEventId: this.lastId }); } catch (e) { /* a listener's bug */ }
      }
    }

    async run() {
      while (!this.closed) {
        try {
          const extra = this.lastId != null ? { 'Last-Event-ID': this.lastId } : {};
          const res = await authFetch(this.url, { headers: extra, signal: this.abort.signal,
                                                  cache: 'no-store' });
          if (res.ok && res.body) await this.read(res.body.getReader());
        } catch (e) { /* dropped: retry below */ }
        if (this.closed) return;
        await new Promise((r) => setTimeout(r, 3000));
      }
    }

    async read(reader) {
      const decoder = new TextDecoder();
      let buffer = '';
      let type = 'message';
      let data = [];
      for (;;) {
        const { value, done } = await reader.read();
        if (done) return;
        buffer += decoder.decode(value, { stream: true });
        let nl;
        while ((nl = buffer.search(/\r\n|\r|\n/)) >= 0) {
          const line = buffer.slice(0, nl);
          buffer = buffer.slice(nl + (buffer.startsWith('\r\n', nl) ? 2 : 1));
          if (line === '') {
            if (data.length) this.dispatch(type, data.join('\n'));
            type = 'message';
            data = [];
            continue;
          }
          if (line.startsWith(':')) continue; // keep-alive comment
          const colon = line.indexOf(':');
          const field = colon < 0 ? line : line.slice(0, colon);
          let v = colon < 0 ? '' : line.slice(colon + 1);
          if (v.startsWith(' ')) v = v.slice(1);
          if (field === 'event') type = v;
          else if (field === 'data') data.push(v);
          else if (field === 'id') this.lastId = v;
        }
      }
    }
  }

  // The browser's EventSource when no token is needed; the fetch reader otherwise.
  function events(url) {
    if (!current() && typeof EventSource !== 'undefined') return new EventSource(url);
    return new FetchEvents(url);
  }

  window.refractAuth = { fetch: authFetch, headers, token: current, events };
})();
