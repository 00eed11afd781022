// The browser page in headless Chromium: it loads, every chapter's image is
// `raylab render`'s bit for bit, a broken scene shows its error at its line,
// a click shows the pixel's ray tree ending in that pixel, and a slider
// renders again. Run by scripts/test.sh:
//   node --test tests/browser/page.test.mjs
// with RAYLAB_PAGE (the built page, scripts/build-web.sh), RAYLAB_BIN (a
// raylab binary) and optionally CHROMIUM (default /usr/bin/chromium).
// Screenshots go to RAYLAB_ARTIFACTS (default target/browser).
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync } from "node:fs";
import { join } from "node:path";
import { tmpdir } from "node:os";
import { chromium } from "playwright-core";
import { serve } from "./serve.mjs";

const PAGE = process.env.RAYLAB_PAGE || "target/web";
const RAYLAB = process.env.RAYLAB_BIN || "target/debug/raylab";
const ARTIFACTS = process.env.RAYLAB_ARTIFACTS || "target/browser";
const WIDTH = 160;
mkdirSync(ARTIFACTS, { recursive: true });

let server;
let browser;
let url;

before(async () => {
  ({ server, url } = await serve(PAGE));
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM || "/usr/bin/chromium", headless: true });
});

after(async () => {
  await browser?.close();
  server?.close();
});

async function openPage(query = "") {
  const page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
  const errors = [];
  page.on("pageerror", (error) => errors.push(error.message));
  // Nothing the page asks for is missing (a favicon.ico it never asked
  // for used to be the server's 404).
  page.on("response", (response) => {
    if (response.status() >= 400) errors.push(`${response.status()} ${response.url()}`);
  });
  await page.goto(url + query);
  await page.waitForFunction(() => ["done", "error", "broken"].includes(document.body.dataset.state), null, { timeout: 60_000 });
  assert.deepEqual(errors, []);
  return page;
}

// Sets an input as a user would, and waits for the render it starts.
async function setInput(page, id, value) {
  const generation = await page.evaluate(() => window.raylabPage.generation);
  await page.evaluate(([id, value]) => {
    const input = document.getElementById(id);
    if (input.type === "checkbox") input.checked = value;
    else input.value = String(value);
    input.dispatchEvent(new Event(input.tagName === "SELECT" ? "change" : "input"));
  }, [id, value]);
  return waitForRender(page, generation);
}

async function waitForRender(page, after) {
  await page.waitForFunction((after) => window.raylabPage.generation > after && ["done", "error"].includes(document.body.dataset.state), after, { timeout: 120_000 });
  return page.evaluate(() => document.body.dataset.state);
}

// FNV-1a of the width, height and RGB bytes: raylab's image hash.
async function canvasHash(page) {
  return page.evaluate(() => {
    const canvas = document.getElementById("image");
    const { data } = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height);
    let hash = 0xcbf29ce484222325n;
    const prime = 0x100000001b3n;
    const mask = (1n << 64n) - 1n;
    const add = (byte) => { hash = ((hash ^ BigInt(byte)) * prime) & mask; };
    for (const size of [canvas.width, canvas.height]) for (let i = 0; i < 4; i++) add((size >>> (8 * i)) & 255);
    for (let i = 0; i < data.length; i += 4) { add(data[i]); add(data[i + 1]); add(data[i + 2]); }
    return { hash: hash.toString(16).padStart(16, "0"), width: canvas.width, height: canvas.height };
  });
}

// Every temporary folder this file makes, so that the last test can
// check that none is left behind.
const madeFolders = [];

function nativeHash(chapter, width, height, extra = []) {
  const folder = mkdtempSync(join(tmpdir(), "raylab-page-"));
  madeFolders.push(folder);
  try {
    const stats = join(folder, "stats.json");
    execFileSync(RAYLAB, ["render", "--chapter", String(chapter), "--width", String(width), "--height", String(height), ...extra, "-o", join(folder, "image.png"), "--stats-json", stats], { stdio: ["ignore", "ignore", "pipe"] });
    return JSON.parse(readFileSync(stats, "utf8")).image_fnv1a64;
  } finally {
    // On every path out, a failed render included.
    rmSync(folder, { recursive: true, force: true });
  }
}

test("the page loads with every chapter and a link to each lesson", async () => {
  const page = await openPage();
  const chapters = await page.$$eval("#chapter option", (options) => options.map((o) => o.value));
  const listed = execFileSync(RAYLAB, ["chapters"], { encoding: "utf8" }).split("\n").filter((line) => /^\s*\d+\s/.test(line));
  assert.equal(chapters.length, listed.length);
  const lesson = await page.getAttribute("#lesson", "href");
  const response = await page.request.get(url + lesson);
  assert.equal(response.status(), 200, lesson);
  assert.match(await response.text(), /Chapter 8: refraction/);
  await page.close();
});

test("every chapter's image is raylab render's, bit for bit", async () => {
  const page = await openPage();
  const count = await page.$$eval("#chapter option", (options) => options.length);
  for (let chapter = 1; chapter <= count; chapter++) {
    await setInput(page, "chapter", chapter);
    assert.equal(await setInput(page, "width", WIDTH), "done", `chapter ${chapter}`);
    const shown = await canvasHash(page);
    assert.equal(shown.width, WIDTH);
    assert.equal(shown.hash, nativeHash(chapter, shown.width, shown.height), `chapter ${chapter} at ${shown.width}x${shown.height}`);
  }
  await page.screenshot({ path: join(ARTIFACTS, "last-chapter.png") });
  await page.close();
});

test("a slider renders again, as the option of raylab render would", async () => {
  const page = await openPage("?chapter=7");
  await setInput(page, "width", WIDTH);
  const before = await canvasHash(page);
  assert.equal(await setInput(page, "samples", 1), "done");
  const after = await canvasHash(page);
  assert.notEqual(after.hash, before.hash);
  assert.equal(after.hash, nativeHash(7, after.width, after.height, ["--samples", "1"]));
  const rays = await page.textContent("#rays");
  assert.match(rays, new RegExp(`Rays: ${after.width * after.height} camera`));
  await page.close();
});

test("switching an effect off renders what raylab render --without renders", async () => {
  const page = await openPage("?chapter=6");
  await setInput(page, "width", WIDTH);
  const generation = await page.evaluate(() => window.raylabPage.generation);
  await page.click('#switches input[data-effect="reflection"]');
  assert.equal(await waitForRender(page, generation), "done");
  const shown = await canvasHash(page);
  assert.equal(shown.hash, nativeHash(6, shown.width, shown.height, ["--without", "reflection"]));
  assert.doesNotMatch(await page.textContent("#effects"), /reflection/);
  await page.close();
});

test("a setting edited in the scene's [render] moves its slider and renders", async () => {
  const page = await openPage("?chapter=7");
  await setInput(page, "width", WIDTH);
  const generation = await page.evaluate(() => window.raylabPage.generation);
  const text = await page.inputValue("#scene");
  assert.match(text, /^samples = 4\b/m);
  await page.fill("#scene", text.replace(/^samples = 4\b/m, "samples = 9"));
  assert.equal(await waitForRender(page, generation), "done");
  assert.equal(await page.inputValue("#samples"), "9");
  const shown = await canvasHash(page);
  assert.equal(shown.hash, nativeHash(7, shown.width, shown.height, ["--samples", "9"]));
  await page.close();
});

test("a broken scene shows its error at the line and column it names", async () => {
  const page = await openPage("?chapter=2");
  const generation = await page.evaluate(() => window.raylabPage.generation);
  await page.fill("#scene", "[camera]\nposition = [0, 1]\n");
  await page.waitForSelector("#scene-error:not([hidden])");
  const message = await page.textContent("#scene-error");
  assert.match(message, /line 2, column 12/);
  const selected = await page.$eval("#scene", (area) => area.value.slice(area.selectionStart, area.selectionEnd));
  assert.equal(selected, "[0, 1]");
  assert.equal(await page.evaluate(() => window.raylabPage.generation), generation, "no render started");
  await page.screenshot({ path: join(ARTIFACTS, "scene-error.png") });
  await page.close();
});

test("a click on a pixel draws its ray tree, which ends in that pixel's colour", async () => {
  const page = await openPage("?chapter=8");
  await setInput(page, "width", 320);
  const { width, height } = await canvasHash(page);
  const [x, y] = [Math.round(width * 0.42), Math.round(height * 0.45)];
  // The middle of pixel (x, y) on the screen, inside the canvas's border.
  const box = await page.$eval("#image", (canvas) => { const r = canvas.getBoundingClientRect(); return [r.left + canvas.clientLeft, r.top + canvas.clientTop, canvas.clientWidth, canvas.clientHeight]; });
  await page.mouse.click(box[0] + ((x + 0.5) * box[2]) / width, box[1] + ((y + 0.5) * box[3]) / height);
  await page.waitForSelector("#pixel-srgb");
  assert.deepEqual(await page.evaluate(() => window.raylabPage.trace.pixel), [x, y]);
  const shown = (await page.textContent("#pixel-srgb")).split(",").map(Number);
  const canvas = await page.evaluate(([x, y]) => Array.from(document.getElementById("image").getContext("2d").getImageData(x, y, 1, 1).data.slice(0, 3)), [x, y]);
  assert.deepEqual(shown, canvas);
  const native = JSON.parse(execFileSync(RAYLAB, ["trace", "--chapter", "8", "--width", String(width), "--height", String(height), "--pixel", `${x},${y}`, "--json"], { encoding: "utf8" }));
  assert.deepEqual(shown, native.srgb);
  // raylab's own page names raylab's command (a workspace's page names
  // its own binary, `cargo run --release --`: src/web.rs's tests).
  assert.match(await page.textContent("#tree-command"), new RegExp(`^raylab trace --chapter 8 .* --pixel ${x},${y}$`));
  const rows = await page.$$eval("#tree tbody tr", (rows) => rows.length);
  const lines = await page.$$eval("#overlay line", (lines) => lines.length);
  assert.ok(rows > 1 && lines >= 1, `${rows} rows, ${lines} lines`);
  // The lines' colours are named under the image.
  const legend = await page.textContent("#legend");
  assert.match(legend, /Lines:.*primary/);
  await page.screenshot({ path: join(ARTIFACTS, "chapter-8-ray-tree.png") });
  await page.close();
});

test("only the sliders the stage reads are shown", async () => {
  const page = await openPage("?chapter=2");
  const hidden = (id) => page.$eval(`#${id}`, (input) => input.closest("label").hidden);
  assert.deepEqual([await hidden("samples"), await hidden("depth"), await hidden("epsilon"), await hidden("width")], [true, true, true, false]);
  assert.equal(await setInput(page, "chapter", 7), "done");
  assert.deepEqual([await hidden("samples"), await hidden("depth"), await hidden("epsilon")], [false, false, false]);
  await page.close();
});

// Declared last: node:test runs a file's tests in order.
test("no temporary folder is left behind", () => {
  assert.ok(madeFolders.length > 0, "the tests above made folders to check");
  const left = madeFolders.filter((folder) => existsSync(folder));
  assert.deepEqual(left, []);
});
