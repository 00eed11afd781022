// The page's render time against raylab render's, one thread each, on the
// same chapter and size: the page with one Web Worker, the command line
// with --threads 1. Prints each median and their ratio; not a test (timings
// on a shared machine are noise). Run by scripts/bench-web.sh.
//   node tests/browser/bench.mjs CHAPTER WIDTH REPEATS
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync } from "node:fs";
import { join } from "node:path";
import { tmpdir } from "node:os";
import { chromium } from "playwright-core";
import { serve } from "./serve.mjs";

const [chapter, width, repeats] = process.argv.slice(2).map(Number);
const PAGE = process.env.RAYLAB_PAGE || "target/web";
const RAYLAB = process.env.RAYLAB_BIN || "target/release/raylab";
const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];

const { server, url } = await serve(PAGE);
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || "/usr/bin/chromium", headless: true });
const page = await browser.newPage();
await page.goto(`${url}?workers=1&chapter=${chapter}`);
await page.waitForFunction(() => document.body.dataset.state === "done");
// The page takes its height from the width and the scene's proportions.
const before = await page.evaluate(() => window.raylabPage.generation);
await page.evaluate((width) => {
  const input = document.getElementById("width");
  input.value = String(width);
  input.dispatchEvent(new Event("input"));
}, width);
await page.waitForFunction((after) => window.raylabPage.generation > after && document.body.dataset.state === "done", before, { timeout: 600_000 });
const [shownWidth, height] = await page.evaluate(() => [document.getElementById("image").width, document.getElementById("image").height]);

const native = [];
const web = [];
const folder = mkdtempSync(join(tmpdir(), "raylab-bench-"));
// Removed however the benchmark ends: done, failed or interrupted.
const removeFolder = () => rmSync(folder, { recursive: true, force: true });
process.on("exit", removeFolder);
for (const signal of ["SIGINT", "SIGTERM", "SIGHUP"]) {
  process.on(signal, () => process.exit(128 + { SIGINT: 2, SIGTERM: 15, SIGHUP: 1 }[signal]));
}
for (let run = 0; run < repeats; run++) {
  // Side by side: one of each per round, so both see the same machine.
  const stats = join(folder, "stats.json");
  execFileSync(RAYLAB, ["render", "--chapter", String(chapter), "--width", String(shownWidth), "--height", String(height), "--threads", "1", "-o", join(folder, "image.png"), "--force", "--stats-json", stats], { stdio: "ignore" });
  native.push(1000 * JSON.parse(readFileSync(stats, "utf8")).seconds);
  const generation = await page.evaluate(() => window.raylabPage.generation);
  await page.evaluate(() => window.raylabPage.rerender());
  await page.waitForFunction((after) => window.raylabPage.generation > after && document.body.dataset.state === "done", generation, { timeout: 600_000 });
  web.push(await page.evaluate(() => window.raylabPage.render.milliseconds));
}
console.log(`chapter ${chapter}, ${shownWidth}x${height}, ${repeats} runs, one thread each`);
console.log(`raylab render --threads 1: median ${median(native).toFixed(1)} ms`);
console.log(`the page, one worker:      median ${median(web).toFixed(1)} ms`);
console.log(`page / native: ${(median(web) / median(native)).toFixed(2)}`);
await browser.close();
server.close();
