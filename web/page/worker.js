// One worker of the page: renders the rows it is sent with its own copy of
// the module, and sends them back. Pixels depend only on the scene, the
// settings and the pixel, so any split of the image puts the same image
// back together.
"use strict";
importScripts("raylab.js");

let module = null;
let raylab = null;

self.onmessage = async (event) => {
  const message = event.data;
  if (message.module) {
    module = message.module;
    raylab = await Raylab.instantiate(module);
    self.postMessage({ ready: true });
    return;
  }
  const { id, job, rows } = message;
  const start = performance.now();
  try {
    const answer = raylab.call({ op: "render", job, rows });
    if (answer.json.error) {
      self.postMessage({ id, rows, error: answer.json.error });
      return;
    }
    const pixels = answer.pixels.slice().buffer;
    self.postMessage(
      { id, rows, pixels, rays: answer.json.rays, milliseconds: performance.now() - start },
      [pixels],
    );
  } catch (error) {
    self.postMessage({ id, rows, error: error.message, panicked: true });
    raylab = await Raylab.instantiate(module);
  }
};
