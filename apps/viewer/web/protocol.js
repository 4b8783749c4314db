// The viewer's side of the wire format (apps/viewer/wire_format.h): arrays arrive as prefix
// deltas ("keep your first `from` elements, append these"), the image as one binary message, the
// figures as JSON text.
'use strict';

const LdsmProtocol = (() => {
  const KIND_TRAJECTORY = 1, KIND_KEYFRAMES = 2, KIND_POINTS = 3, KIND_IMAGE = 4;

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

  // Decodes one binary message into {kind, from, total, floats} or {kind: 4, image}.
  function decodeBinary(buffer) {
    if (buffer.byteLength < 16) return null;
    const h = new DataView(buffer);
    const kind = h.getUint32(0, true);
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

  return { Stream, decodeBinary, KIND_TRAJECTORY, KIND_KEYFRAMES, KIND_POINTS, KIND_IMAGE };
})();
