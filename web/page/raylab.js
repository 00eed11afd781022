// The loader of raylab's WebAssembly module, for the page and its workers.
// The module exports one call: a JSON request in, an answer out (the JSON's
// length in 4 bytes, the JSON, then a render's pixels); see src/web.rs.
"use strict";

class ChapterPanic extends Error {}

class Raylab {
  constructor(instance) {
    this.exports = instance.exports;
  }

  static async instantiate(module) {
    // The module imports nothing: no JavaScript glue to keep in step.
    return new Raylab(await WebAssembly.instantiate(module, {}));
  }

  // Answers `request`: { json, pixels }. A chapter that panics ends the
  // module (WebAssembly cannot unwind); its message is thrown as a
  // ChapterPanic, and this instance must not be called again.
  call(request) {
    const exports = this.exports;
    const bytes = new TextEncoder().encode(JSON.stringify(request));
    const pointer = exports.raylab_alloc(bytes.length);
    new Uint8Array(exports.memory.buffer, pointer, bytes.length).set(bytes);
    try {
      exports.raylab_call(pointer, bytes.length);
    } catch (trap) {
      let message = `the module stopped: ${trap}`;
      try {
        const answer = this.answer();
        if (answer.json && answer.json.error) message = answer.json.error;
      } catch (_) {
        // No answer was left: the trap's own message it is.
      }
      throw new ChapterPanic(message);
    }
    exports.raylab_free(pointer, bytes.length);
    return this.answer();
  }

  answer() {
    const exports = this.exports;
    const pointer = exports.raylab_answer_ptr();
    const length = exports.raylab_answer_len();
    const bytes = new Uint8Array(exports.memory.buffer, pointer, length).slice();
    const jsonLength = new DataView(bytes.buffer).getUint32(0, true);
    const json = JSON.parse(new TextDecoder().decode(bytes.subarray(4, 4 + jsonLength)));
    return { json, pixels: bytes.subarray(4 + jsonLength) };
  }
}

if (typeof self !== "undefined") {
  self.Raylab = Raylab;
  self.ChapterPanic = ChapterPanic;
}
