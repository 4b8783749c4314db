// The viewer's side of the wire format (apps/viewer/wire_format.h): the response to GET /stream
// is a sequence of records (u32 length, then the message); arrays arrive as prefix deltas ("keep
// your first `from` elements, append these"), the image as one message, the figures as JSON.
'use strict';

const LdsmProtocol = (() => {
  const KIND_TRAJECTORY = 1, KIND_KEYFRAMES = 2, KIND_POINTS = 3, KIND_IMAGE = 4;
  const KIND_FIGURES = 5;
  const MAX_MESSAGE_BYTES = 64 << 20;  // far above the largest the server sends (about 2 MB)

  // Cuts the bytes of the stream, as they arrive in pieces of any size, into messages: each an
  // ArrayBuffer of its own (so that typed arrays over it are aligned). Throws on a length over
  // MAX_MESSAGE_BYTES (the page then reconnects).
  class RecordReader {
    constructor() {
      this.pieces = [];  // Uint8Arrays not yet consumed
      this.buffered = 0;
    }
    // Appends a piece; returns the messages completed by it.
    push(piece) {
      if (piece.byteLength > 0) {
        this.pieces.push(piece);
        this.buffered += piece.byteLength;
      }
      const out = [];
      for (;;) {
        if (this.buffered < 4) return out;
        const head = this.peek(4);
        const length = new DataView(head.buffer).getUint32(0, true);
        if (length > MAX_MESSAGE_BYTES) throw new Error(`message of ${length} bytes`);
        if (this.buffered < 4 + length) return out;
        this.take(4);
        out.push(this.take(length).buffer);
      }
    }
    // The first n buffered bytes, copied (n <= buffered).
    peek(n) {
      const out = new Uint8Array(n);
      let at = 0;
      for (const p of this.pieces) {
        const k = Math.min(n - at, p.byteLength);
        out.set(p.subarray(0, k), at);
        at += k;
        if (at === n) break;
      }
      return out;
    }
    // Removes and returns the first n buffered bytes, in a new buffer.
    take(n) {
      const out = this.peek(n);
      let left = n;
      while (left > 0) {
        const p = this.pieces[0];
        if (p.byteLength <= left) {
          left -= p.byteLength;
          this.pieces.shift();
        } else {
          this.pieces[0] = p.subarray(left);
          left = 0;
        }
      }
      this.buffered -= n;
      return out;
    }
  }

  // A growable float array of `stride` floats per element.
  class Stream {
    constructor(stride) {
      this.stride = stride;
      this.data = new Float32Array(stride * 1024);
      this.length = 0;       // elements
      this.changedFrom = 0;  // first element changed since the scene last looked
    }
    reset() { this.length = 0; this.changedFrom = 0; }
    // Keeps the first `from` elements and appends `floats`; false when the message does not fit
    // what the page holds (it then waits for the next full update).
    apply(from, floats, total) {
      if (from > this.length || from + floats.length / this.stride !== total) return false;
      const need = total * this.stride;
      if (need > this.data.length) {
        let cap = this.data.length;
        while (cap < need) cap *= 2;
        const grown = new Float32Array(cap);
        grown.set(this.data.subarray(0, from * this.stride));
        this.data = grown;
      }
      this.data.set(floats, from * this.stride);
      this.length = total;
      this.changedFrom = Math.min(this.changedFrom, from);
      return true;
    }
  }

  const utf8 = new TextDecoder();

  // Decodes one message into {kind, from, total, floats}, {kind: 4, image} or
  // {kind: 5, figures}; null when it is not one.
  function decodeMessage(buffer) {
    if (buffer.byteLength < 4) return null;
    const h = new DataView(buffer);
    const kind = h.getUint32(0, true);
    if (kind === KIND_FIGURES) {
      try {
        return { kind, figures: JSON.parse(utf8.decode(new Uint8Array(buffer, 4))) };
      } catch (e) {
        return null;
      }
    }
    if (buffer.byteLength < 16) return null;
    if (kind === KIND_IMAGE) {
      const width = h.getUint32(4, true), height = h.getUint32(8, true);
      const count = h.getUint32(12, true);
      const pixelBytes = width * height;
      const pointsAt = 16 + Math.ceil(pixelBytes / 4) * 4;
      if (buffer.byteLength < pointsAt + count * 8) return null;
      return {
        kind,
        image: {
          width, height,
          pixels: new Uint8Array(buffer, 16, pixelBytes),
          points: new Float32Array(buffer, pointsAt, count * 2),
        },
      };
    }
    const from = h.getUint32(4, true), count = h.getUint32(8, true), total = h.getUint32(12, true);
    const stride = kind === KIND_POINTS ? 4 : 7;
    if (buffer.byteLength !== 16 + count * stride * 4) return null;
    return { kind, from, total, floats: new Float32Array(buffer, 16, count * stride) };
  }

  return { Stream, RecordReader, decodeMessage, KIND_TRAJECTORY, KIND_KEYFRAMES, KIND_POINTS,
    KIND_IMAGE, KIND_FIGURES };
})();
