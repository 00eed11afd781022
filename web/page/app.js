// The page: a chapter's image rendered by workers, its scene in an editor,
// its settings on sliders, and the ray tree of the pixel clicked.
"use strict";

const $ = (id) => document.getElementById(id);
const ROWS_A_TASK = 4;
const MAX_HEIGHT = 2048;
// Keyed by the kinds' names, as raylab writes them (`RayKind::name`).
const KIND_COLOURS = { primary: "#ffd400", reflection: "#2f7bff", refraction: "#11b35b", shadow: "#ff8c00", bounce: "#c04bd8", light: "#ffffff", to_camera: "#999999" };

const page = {
  module: null,
  raylab: null, // the main thread's instance: chapters, prepare, trace
  chapters: [],
  workers: [],
  render: null, // the render in progress or last finished
  generation: 0,
  sceneEdited: false,
};
// What the browser tests and the benchmark read (and `rerender`, which
// the benchmark calls to time the same render again).
window.raylabPage = page;
page.rerender = () => startRender();

// A call on the main thread's instance. A chapter that panics there (a
// student's tree still todo!(), say) ends that instance: its message comes
// back as an error, and a fresh instance takes its place.
function mainCall(request) {
  try {
    return page.raylab.call(request).json;
  } catch (error) {
    if (!(error instanceof ChapterPanic)) throw error;
    page.raylab = null;
    Raylab.instantiate(page.module).then((fresh) => { page.raylab = fresh; });
    return { error: error.message, panicked: true };
  }
}

function setState(state) {
  document.body.dataset.state = state;
}

function status(text) {
  $("status").textContent = text;
}

async function start() {
  const bytes = await (await fetch("raylab.wasm")).arrayBuffer();
  page.module = await WebAssembly.compile(bytes);
  page.raylab = await Raylab.instantiate(page.module);
  const course = page.raylab.call({ op: "chapters" }).json;
  // How these chapters run on the command line (a workspace's own binary).
  page.command = course.command || "raylab";
  page.chapters = course.chapters;
  for (const chapter of page.chapters) {
    const option = document.createElement("option");
    option.value = chapter.number;
    option.textContent = `${chapter.number}. ${chapter.title}`;
    $("chapter").append(option);
  }
  // One worker a core, or as many as ?workers=N asks (the benchmark: 1).
  const asked = Number(new URLSearchParams(location.search).get("workers"));
  const cores = Math.max(1, Math.min(asked || navigator.hardwareConcurrency || 2, 16));
  await Promise.all(Array.from({ length: cores }, () => addWorker()));
  // raylab's own page opens at chapter 8, a workspace's at chapter 1.
  const wanted = Number(new URLSearchParams(location.search).get("chapter")) || course.start;
  $("chapter").value = String(page.chapters.some((c) => c.number === wanted) ? wanted : course.start);
  chapterChanged();
  for (const id of ["width", "samples", "depth", "epsilon", "fixed-epsilon"]) {
    $(id).addEventListener("input", () => { showValues(); scheduleRender(); });
  }
  $("chapter").addEventListener("change", chapterChanged);
  $("scene").addEventListener("input", () => { page.sceneEdited = true; scheduleRender(400); });
  $("image").addEventListener("click", pixelClicked);
}

function addWorker() {
  return new Promise((resolve) => {
    const worker = new Worker("worker.js");
    const entry = { worker, busy: false };
    worker.onmessage = (event) => {
      if (event.data.ready) {
        page.workers.push(entry);
        resolve(entry);
        return;
      }
      entry.busy = false;
      rowsDone(event.data);
      dispatch();
    };
    worker.postMessage({ module: page.module });
  });
}

// A chapter starts from its built-in scene's own settings: the page then
// shows what `raylab render --chapter N --width W` renders.
function chapterChanged() {
  const chapter = currentChapter();
  $("scene").value = chapter.scene;
  page.sceneEdited = false;
  page.own = null;
  $("switches").querySelectorAll("label").forEach((label) => label.remove());
  $("lesson").href = `doc/raylab/chapters/${chapter.module}/index.html`;
  $("lesson").textContent = `lesson ${chapter.number}: ${chapter.title}`;
  clearTree();
  scheduleRender(0);
}

// The scene's own [render] settings, as the editor holds them: each one
// that changed since they were last read moves its slider or box, so an
// edit of `samples = 16` in the scene is what the next render uses. (The
// page's width is at most 320 at first, for speed.)
function adoptSceneSettings(own) {
  const last = page.own;
  const changed = (read) => !last || JSON.stringify(read(own)) !== JSON.stringify(read(last));
  if (changed((o) => o.width)) $("width").value = String(Math.min(own.width, last ? 800 : 320));
  if (changed((o) => o.settings.samples)) $("samples").value = String(own.settings.samples);
  if (changed((o) => o.settings.depth)) $("depth").value = String(own.settings.depth);
  if (changed((o) => o.settings.epsilon)) {
    $("fixed-epsilon").checked = own.settings.epsilon !== null;
    if (own.settings.epsilon !== null) $("epsilon").value = String(Math.log10(own.settings.epsilon));
  }
  if (changed((o) => [o.switchable, o.without])) {
    // One box per effect of the stage that can be left out: the image
    // without it is `raylab render --without NAME`'s.
    const switches = $("switches");
    switches.querySelectorAll("label").forEach((label) => label.remove());
    for (const name of own.switchable) {
      const label = document.createElement("label");
      const box = document.createElement("input");
      box.type = "checkbox";
      box.checked = own.on.includes(name);
      box.dataset.effect = name;
      box.addEventListener("input", () => scheduleRender());
      label.append(box, name);
      switches.append(label);
    }
  }
  page.own = own;
  showValues();
}

// Ticks the boxes of the effects the stage simulates: leaving one out
// leaves out what is built on it (chapter 8's glass casts reflection rays).
function showSwitches(prepared) {
  for (const box of document.querySelectorAll("#switches input")) {
    box.checked = prepared.on.includes(box.dataset.effect);
  }
}

function currentChapter() {
  return page.chapters.find((c) => c.number === Number($("chapter").value));
}

function showValues() {
  for (const output of document.querySelectorAll("output")) {
    const input = $(output.htmlFor.value);
    output.textContent = input.id === "epsilon" ? epsilon().toExponential(1) : input.value;
  }
  $("epsilon").disabled = !$("fixed-epsilon").checked;
}

function epsilon() {
  return Math.pow(10, Number($("epsilon").value));
}

// The job every worker renders a share of: the chapter, the scene's text
// (null: the built-in scene, exactly as `raylab render --chapter N`) and
// the sliders, which mean what raylab render's options mean.
function job(own) {
  const width = Number($("width").value);
  const [sceneWidth, sceneHeight] = [own.width, own.height];
  return {
    chapter: currentChapter().number,
    scene: page.sceneEdited ? $("scene").value : null,
    width,
    // The scene's proportions, within a height the page can show.
    height: Math.min(MAX_HEIGHT, Math.max(1, Math.round((width * sceneHeight) / sceneWidth))),
    samples: Number($("samples").value),
    depth: Number($("depth").value),
    epsilon: $("fixed-epsilon").checked ? epsilon() : null,
    without: Array.from(document.querySelectorAll("#switches input:not(:checked)"), (box) => box.dataset.effect),
  };
}

let renderTimer = null;
function scheduleRender(delay = 150) {
  clearTimeout(renderTimer);
  renderTimer = setTimeout(startRender, delay);
}

function startRender() {
  if (!page.raylab) {
    // The main instance is being replaced after a panic.
    scheduleRender(50);
    return;
  }
  const chapter = currentChapter().number;
  const own = mainCall({ op: "prepare", job: { chapter, scene: page.sceneEdited ? $("scene").value : null } });
  if (own.error) {
    showSceneError(own);
    $("switches").querySelectorAll("label").forEach((label) => label.remove());
    page.own = null;
    setState("error");
    return;
  }
  adoptSceneSettings(own);
  const request = job(own);
  const prepared = mainCall({ op: "prepare", job: request });
  if (prepared.error) {
    showSceneError(prepared);
    setState("error");
    return;
  }
  showSceneError(null);
  showSwitches(prepared);
  // Only the sliders this stage reads: samples before supersampling, say,
  // would change nothing.
  for (const [name, used] of Object.entries(prepared.uses)) $(name).closest("label").hidden = !used;
  // The scene's own width, when the slider renders at another.
  $("scene-width").textContent = own.width === prepared.width ? "" : ` (the scene says ${own.width})`;
  stopWorkers();
  const id = ++page.generation;
  const canvas = $("image");
  canvas.width = prepared.width;
  canvas.height = prepared.height;
  const scale = Math.max(1, Math.floor(640 / prepared.width));
  canvas.style.width = `${prepared.width * scale}px`;
  canvas.style.height = `${prepared.height * scale}px`;
  $("overlay").setAttribute("width", prepared.width * scale);
  $("overlay").setAttribute("height", prepared.height * scale);
  $("overlay").setAttribute("viewBox", `0 0 ${prepared.width} ${prepared.height}`);
  $("overlay").replaceChildren();
  $("effects").textContent = `Simulated: ${prepared.effects.join(", ") || "nothing"} (${prepared.samples} sample${prepared.samples === 1 ? "" : "s"} a pixel)`;
  const tasks = [];
  for (let row = 0; row < prepared.height; row += ROWS_A_TASK) {
    tasks.push([row, Math.min(prepared.height, row + ROWS_A_TASK)]);
  }
  page.render = {
    id, job: request, prepared, tasks, pending: tasks.length, started: performance.now(),
    rays: { primary: 0, shadow: 0, reflection: 0, refraction: 0, bounce: 0, light: 0, to_camera: 0 }, error: null,
  };
  setState("rendering");
  status("rendering…");
  dispatch();
}

// Workers still busy with an older render are replaced: a render can take
// long (or a chapter loop for ever), and its rows would be thrown away.
function stopWorkers() {
  for (const entry of page.workers.filter((e) => e.busy)) {
    entry.worker.terminate();
    page.workers.splice(page.workers.indexOf(entry), 1);
    addWorker().then(dispatch);
  }
}

function dispatch() {
  const render = page.render;
  if (!render || render.error) return;
  for (const entry of page.workers) {
    if (entry.busy || render.tasks.length === 0) continue;
    entry.busy = true;
    entry.worker.postMessage({ id: render.id, job: render.job, rows: render.tasks.shift() });
  }
}

function rowsDone(message) {
  const render = page.render;
  if (!render || message.id !== render.id) return;
  if (message.error) {
    // An error while rendering rows is the chapters' (a panic, a chapter
    // not written yet), not the scene's, which prepared without one.
    render.error = message.error;
    status("the chapters stopped (under the image)");
    $("chapter-error").hidden = false;
    $("chapter-error").textContent = message.error;
    setState("error");
    return;
  }
  const [first, end] = message.rows;
  const image = new ImageData(new Uint8ClampedArray(message.pixels), render.prepared.width, end - first);
  $("image").getContext("2d").putImageData(image, 0, first);
  for (const kind of Object.keys(render.rays)) render.rays[kind] += message.rays[kind];
  render.pending -= 1;
  const rays = render.rays;
  const bounces = (rays.bounce > 0 ? `, ${rays.bounce} bounce` : "")
    + (rays.light > 0 ? `, ${rays.light} light, ${rays.to_camera} to camera` : "");
  $("rays").textContent = `Rays: ${rays.primary} camera, ${rays.shadow} shadow, ${rays.reflection} reflection, ${rays.refraction} refraction${bounces}`;
  if (render.pending === 0) {
    render.milliseconds = performance.now() - render.started;
    const workers = page.workers.length;
    status(`rendered ${render.prepared.width}x${render.prepared.height} in ${render.milliseconds.toFixed(0)} ms on ${workers} worker${workers === 1 ? "" : "s"}`);
    setState("done");
  }
}

function showSceneError(answer) {
  const box = $("scene-error");
  const chapters = $("chapter-error");
  box.hidden = true;
  chapters.hidden = true;
  if (!answer) return;
  if (answer.panicked) {
    // The chapters' own message (a `todo!()` not written yet, a panic),
    // beside the image it stopped, not in the scene's error slot.
    chapters.hidden = false;
    chapters.textContent = answer.error;
    status("the chapters stopped (under the image)");
    return;
  }
  box.hidden = false;
  box.textContent = answer.error;
  status("the scene has an error");
  if (answer.line) {
    // Select the line the error names, so the editor shows where it is.
    const lines = $("scene").value.split("\n");
    const startOfLine = lines.slice(0, answer.line - 1).reduce((n, line) => n + line.length + 1, 0);
    const at = startOfLine + Math.max(0, (answer.column || 1) - 1);
    const end = startOfLine + (lines[answer.line - 1] || "").length;
    $("scene").setSelectionRange(at, Math.max(at, end));
  }
}

function pixelClicked(event) {
  const render = page.render;
  if (!render || render.error) return;
  const canvas = $("image");
  // The image starts inside the canvas's border.
  const box = canvas.getBoundingClientRect();
  const left = event.clientX - box.left - canvas.clientLeft;
  const top = event.clientY - box.top - canvas.clientTop;
  const x = Math.min(canvas.width - 1, Math.max(0, Math.floor((left / canvas.clientWidth) * canvas.width)));
  const y = Math.min(canvas.height - 1, Math.max(0, Math.floor((top / canvas.clientHeight) * canvas.height)));
  showTrace(x, y);
}

function showTrace(x, y) {
  if (!page.raylab) return;
  const answer = mainCall({ op: "trace", job: page.render.job, pixel: [x, y] });
  if (answer.error) {
    $("pixel-value").textContent = answer.error;
    return;
  }
  page.trace = answer;
  drawTree(answer);
  listTree(answer);
  // The table is below the image on a small screen: bring its top into view.
  $("tree-panel").scrollIntoView({ block: "nearest" });
}

function clearTree() {
  $("overlay").replaceChildren();
  $("legend").replaceChildren();
  $("tree").tBodies[0].replaceChildren();
  $("pixel-value").textContent = "";
  $("tree-command").textContent = "";
  $("tree-title").textContent = "Ray tree";
}

function drawTree(trace) {
  const overlay = $("overlay");
  overlay.replaceChildren();
  const svg = (name, attributes) => {
    const element = document.createElementNS("http://www.w3.org/2000/svg", name);
    for (const [key, value] of Object.entries(attributes)) element.setAttribute(key, value);
    overlay.append(element);
    return element;
  };
  const draw = (ray) => {
    if (ray.screen) {
      const [[x1, y1], [x2, y2]] = ray.screen;
      const blocked = ray.kind === "shadow" && ray.hit;
      svg("line", {
        x1, y1, x2, y2,
        stroke: blocked ? "#888" : KIND_COLOURS[ray.kind],
        "stroke-width": 1.5,
        "vector-effect": "non-scaling-stroke",
        "stroke-dasharray": ray.kind === "shadow" ? "4 3" : "none",
        class: `ray ${ray.kind}`,
      });
      if (ray.hit && ray.kind !== "shadow") {
        svg("circle", { cx: x2, cy: y2, r: 3, fill: KIND_COLOURS[ray.kind], "vector-effect": "non-scaling-stroke", class: "hit" });
      }
    }
    ray.children.forEach(draw);
  };
  trace.samples.forEach((sample) => draw(sample.ray));
  const [x, y] = trace.pixel;
  svg("rect", { x, y, width: 1, height: 1, fill: "none", stroke: "#fff", "stroke-width": 1, "vector-effect": "non-scaling-stroke" });
  showLegend(trace);
}

// What each line's colour means, for the kinds of ray this tree has.
function showLegend(trace) {
  const kinds = new Set();
  const collect = (ray) => {
    kinds.add(ray.kind);
    ray.children.forEach(collect);
  };
  trace.samples.forEach((sample) => collect(sample.ray));
  const legend = $("legend");
  legend.replaceChildren("Lines:");
  for (const kind of Object.keys(KIND_COLOURS).filter((kind) => kinds.has(kind))) {
    const line = document.createElement("span");
    line.className = "legend-line";
    line.style.borderColor = KIND_COLOURS[kind];
    if (kind === "shadow") line.style.borderTopStyle = "dashed";
    legend.append(line, kind.replace("_", " "));
  }
  if (kinds.has("shadow")) {
    const line = document.createElement("span");
    line.className = "legend-line";
    line.style.borderColor = "#888";
    line.style.borderTopStyle = "dashed";
    legend.append(line, "blocked shadow");
  }
}

const number = (value) => (value === null || value === undefined ? "" : Number(value).toPrecision(4));
const triple = (values) => (values ? values.map((value) => Number(value).toFixed(4)).join(", ") : "");
function swatch(values) {
  if (!values) return "";
  const [r, g, b] = values.map((value) => Math.round(255 * Math.min(1, Math.max(0, value)) ** (1 / 2.2)));
  return `<span class="swatch" style="background: rgb(${r}, ${g}, ${b})"></span>`;
}

function listTree(trace) {
  const body = $("tree").tBodies[0];
  body.replaceChildren();
  let index = 0;
  const list = (ray, depth, sample) => {
    const row = body.insertRow();
    row.className = `ray ${ray.kind}`;
    const met = ray.hit
      ? `${ray.hit.name} (shape ${ray.hit.shape})`
      : ray.kind === "shadow" ? `nothing: light ${ray.light} lights the point` : "nothing: the background";
    const cells = [
      `${"&nbsp;".repeat(2 * depth)}${index++}${sample === null ? "" : ` (sample ${sample})`}`,
      ray.kind,
      ray.kind === "shadow" && ray.hit ? `blocked by ${ray.hit.name}` : met,
      ray.hit ? number(ray.hit.t) : "",
      number(ray.weight),
      ray.color ? swatch(ray.color) + triple(ray.color) : "",
      triple(ray.contribution),
      ray.running_sum ? swatch(ray.running_sum) + triple(ray.running_sum) : "",
    ];
    cells.forEach((content, column) => {
      // Names come from the scene: text, never markup.
      if (column === 2) row.insertCell().textContent = content;
      else row.insertCell().innerHTML = content;
    });
    ray.children.forEach((child) => list(child, depth + 1, null));
  };
  trace.samples.forEach((sample) => list(sample.ray, 0, sample.sample));
  const [x, y] = trace.pixel;
  const [r, g, b] = trace.srgb;
  const job = page.render.job;
  $("tree-title").textContent = `Ray tree of pixel ${x},${y} (${trace.sample_count} sample${trace.sample_count === 1 ? "" : "s"})`;
  $("tree-command").textContent = `${page.command} trace --chapter ${job.chapter} --width ${job.width} --height ${job.height} --samples ${job.samples} --depth ${job.depth}${job.epsilon === null ? "" : ` --epsilon ${job.epsilon}`}${job.without.length ? ` --without ${job.without.join(",")}` : ""} --pixel ${x},${y}${job.scene === null ? "" : " --scene YOUR-SCENE.toml"}`;
  $("pixel-value").innerHTML = `${swatch(trace.color)}pixel ${x},${y}: linear ${triple(trace.color)} → sRGB <span id="pixel-srgb">${r}, ${g}, ${b}</span>, as the render writes it`;
}

start().catch((error) => {
  status(`the page could not start: ${error.message}`);
  setState("broken");
});
