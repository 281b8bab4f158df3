// mjpeg.js - reads a view's frame stream (multipart/x-mixed-replace of JPEG parts,
// docs/views.md "The stream") with fetch, and hands each part to the viewer with its
// headers (X-Frame-Seq, X-Frame-Kind, X-Render-Time-Ms, X-Refract-Irradiance).
//
// Why not <img src=".../stream">: Chromium shows a part of a multipart image only when
// the headers of the NEXT part have arrived. refractd sends a frame only when something
// changed, so in such an <img> every frame would stay off screen until the next change
// (or the 15 s keep-alive). Reading the parts here shows each one as soon as its last byte
// is in, and gives the viewer each frame's number and timings.
//
// Parts are cut by their Content-Length (refractd always sends it); a part without one
// ends at the next delimiter. Bytes are kept in one growing buffer that is compacted as
// parts are consumed, so a long session does not accumulate memory.
'use strict';

window.RefractMjpeg = (function () {
  const CRLF2 = [13, 10, 13, 10];
  const decoder = new TextDecoder('latin1');

  function indexOf(bytes, pattern, from, end) {
    const last = end - pattern.length;
    outer:
    for (let i = from; i <= last; i++) {
      for (let j = 0; j < pattern.length; j++) {
        if (bytes[i + j] !== pattern[j]) continue outer;
      }
      return i;
    }
    return -1;
  }

  class ByteQueue {
    constructor() {
      this.buf = new Uint8Array(1 << 16);
      this.start = 0;
      this.end = 0;
    }
    get length() { return this.end - this.start; }
    push(chunk) {
      if (this.end + chunk.length > this.buf.length) {
        // Move what is left to the front; grow only when that is not enough.
        const used = this.length;
        let size = this.buf.length;
        while (size < used + chunk.length) size *= 2;
        if (size === this.buf.length) {
          this.buf.copyWithin(0, this.start, this.end);
        } else {
          const grown = new Uint8Array(size);
          grown.set(this.buf.subarray(this.start, this.end));
          this.buf = grown;
        }
        this.start = 0;
        this.end = used;
      }
      this.buf.set(chunk, this.end);
      this.end += chunk.length;
    }
    // The offset of pattern at or after `from` (offsets count from the first byte held).
    find(pattern, from) {
      const i = indexOf(this.buf, pattern, this.start + (from || 0), this.end);
      return i < 0 ? -1 : i - this.start;
    }
    take(n) { // a copy of the first n bytes, consumed
      const out = this.buf.slice(this.start, this.start + n);
      this.start += n;
      return out;
    }
    skip(n) { this.start += n; }
  }

  function parseHeaders(text) {
    const headers = {};
    for (const line of text.split('\r\n')) {
      const colon = line.indexOf(':');
      if (colon > 0) headers[line.slice(0, colon).trim().toLowerCase()] = line.slice(colon + 1).trim();
    }
    return headers;
  }

  // Reads the stream at url until it ends or `signal` aborts. Calls onFrame({blob, seq,
  // kind, renderMs, irradiance}) for each part. Resolves when the stream ends; rejects
  // with an Error (with .status for an HTTP error answer) when it cannot be read.
  async function read(url, { signal, onFrame }) {
    const res = await window.refractAuth.fetch(url, { signal, cache: 'no-store' });
    if (!res.ok) {
      let message = `${url}: HTTP ${res.status}`;
      try { message = (await res.json()).error.message; } catch (e) { /* not JSON */ }
      const err = new Error(message);
      err.status = res.status;
      throw err;
    }
    const type = res.headers.get('Content-Type') || '';
    const m = /boundary="?([^";]+)"?/i.exec(type);
    if (!/^multipart\//i.test(type) || !m) throw new Error(`${url}: not a multipart stream (${type})`);
    const delimiter = new TextEncoder().encode('--' + m[1]);
    const q = new ByteQueue();
    const reader = res.body.getReader();
    let phase = 'delimiter';
    let headers = null;
    for (;;) {
      const { value, done } = await reader.read();
      if (done) return;
      q.push(value);
      for (;;) {
        if (phase === 'delimiter') {
          // Skip to the end of the delimiter line (anything before it is the CRLF that
          // ends the previous part, or a preamble).
          const at = q.find(delimiter);
          if (at < 0) break;
          const lineEnd = q.find([13, 10], at + delimiter.length);
          if (lineEnd < 0) break;
          q.skip(lineEnd + 2);
          phase = 'headers';
        } else if (phase === 'headers') {
          const at = q.find(CRLF2);
          if (at < 0) break;
          headers = parseHeaders(decoder.decode(q.take(at)));
          q.skip(4);
          phase = 'body';
        } else {
          const len = parseInt(headers['content-length'], 10);
          let body;
          if (Number.isFinite(len) && len >= 0) {
            if (q.length < len) break;
            body = q.take(len);
          } else {
            const at = q.find(delimiter);
            if (at < 0) break;
            body = q.take(Math.max(0, at - 2)); // the CRLF before the delimiter
          }
          phase = 'delimiter';
          onFrame({
            blob: new Blob([body], { type: headers['content-type'] || 'image/jpeg' }),
            seq: Number(headers['x-frame-seq']),
            kind: headers['x-frame-kind'] || null,
            renderMs: headers['x-render-time-ms'] != null ? Number(headers['x-render-time-ms']) : null,
            irradiance: headers['x-refract-irradiance'] || null,
          });
        }
      }
    }
  }

  return { read };
})();
