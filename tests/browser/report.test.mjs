// `raylab grade`'s HTML reports in headless Chromium at 1280 px wide: the
// students' statuses come before the similar code, nothing runs off the
// page to the right, every image loads, and the overview gives the reason
// beside "error". Run by scripts/test-browser.sh:
//   node --test tests/browser/report.test.mjs
// with RAYLAB_BIN (a raylab binary; cargo on the PATH builds the class's
// workspaces) and optionally CHROMIUM (default /usr/bin/chromium).
// Screenshots go to RAYLAB_ARTIFACTS (default target/browser).
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync, spawnSync } from "node:child_process";
import { copyFileSync, mkdirSync, mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { join, resolve } from "node:path";
import { tmpdir } from "node:os";
import { pathToFileURL } from "node:url";
import { chromium } from "playwright-core";

const RAYLAB = resolve(process.env.RAYLAB_BIN || "target/debug/raylab");
const ARTIFACTS = process.env.RAYLAB_ARTIFACTS || "target/browser";
const WIDTH = 1280;
mkdirSync(ARTIFACTS, { recursive: true });

let browser;
let dir;

before(async () => {
  dir = mkdtempSync(join(tmpdir(), "raylab-report-"));
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM || "/usr/bin/chromium", headless: true });
});

after(async () => {
  await browser?.close();
  if (dir) rmSync(dir, { recursive: true, force: true });
});

// Grades `class` with `args`; exit status 1 (some students fail) is what
// these classes give.
function grade(args) {
  const run = spawnSync(RAYLAB, ["grade", ...args], { cwd: dir, encoding: "utf8" });
  assert.equal(run.status, 1, `raylab grade ${args.join(" ")}: ${run.stderr}`);
}

// Opens `report` at 1280 px and returns the page.
async function open(report, name) {
  const page = await browser.newPage({ viewport: { width: WIDTH, height: 900 } });
  await page.goto(pathToFileURL(join(dir, report)).href);
  await page.waitForLoadState("load");
  await page.screenshot({ path: join(ARTIFACTS, `${name}.png`), fullPage: true });
  return page;
}

// Every element whose right edge is past the page's width, described.
async function overflowing(page) {
  return page.evaluate(() => {
    const width = document.documentElement.clientWidth;
    const past = [...document.querySelectorAll("body *")]
      .filter((element) => element.getBoundingClientRect().right > width + 1)
      .map((element) => `${element.tagName.toLowerCase()}.${element.className}: right ${Math.round(element.getBoundingClientRect().right)}`);
    if (document.documentElement.scrollWidth > width) past.push(`the page scrolls sideways: ${document.documentElement.scrollWidth} > ${width}`);
    return past;
  });
}

// A workspace whose src/ is `code`: two students with the same code make
// the report's similar code section.
function workspace(class_, student, code) {
  mkdirSync(join(dir, class_, student, "src"), { recursive: true });
  writeFileSync(join(dir, class_, student, "Cargo.toml"), `[package]\nname = "${student}"\nversion = "0.1.0"\nedition = "2021"\n`);
  writeFileSync(join(dir, class_, student, "src", "main.rs"), code);
}

const SHARED_CODE = `fn main() {
    let values: Vec<f64> = (0..100).map(|i| i as f64 * 0.5).collect();
    let total: f64 = values.iter().map(|value| value * value + 2.0 * value - 1.0).sum::<f64>() + values.iter().copied().fold(0.0, f64::max) * 3.0 - values.len() as f64 + values.iter().map(|value| value.sqrt()).sum::<f64>();
    let unbroken = "${"x".repeat(400)}";
    let mut sorted = values.clone();
    sorted.sort_by(|a, b| b.partial_cmp(a).unwrap_or(std::cmp::Ordering::Equal));
    for (index, value) in sorted.iter().enumerate().take(10) { if index % 2 == 0 { println!("{index} {value} {total}"); } else { eprintln!("{value} {unbroken}"); } }
    let words = ["alpha", "beta", "gamma", "delta"];
    let joined = words.iter().map(|word| word.to_uppercase()).collect::<Vec<_>>().join("-");
    println!("{joined} {}", joined.len() * 2 + words.len());
}
`;

test("grade --code: statuses with their reasons come before the similar code, which stays inside the page", async () => {
  workspace("code", "ann", SHARED_CODE);
  workspace("code", "zoe", SHARED_CODE);
  workspace("code", "bob", "fn main() { this is not Rust }\n");
  // Trusted code, written here: no sandbox needed to build and run it.
  grade(["--code", "code", "--no-sandbox", "--timeout", "120"]);
  const page = await open("code/report.html", "report-code");
  const tops = await page.evaluate(() => {
    const top = (element) => element && element.getBoundingClientRect().top + window.scrollY;
    return {
      overview: top(document.querySelector("table.summary")),
      sections: [...document.querySelectorAll("section.chapter")].map(top),
      similar: top(document.getElementById("similar-code")),
    };
  });
  assert.ok(tops.similar !== undefined && tops.similar !== null, "the report has a similar code section");
  assert.equal(tops.sections.length, 3);
  for (const status of [tops.overview, ...tops.sections]) {
    assert.ok(status < tops.similar, `a status at ${status} px is below the similar code at ${tops.similar} px`);
  }
  const results = await page.$$eval("table.summary td:last-child", (cells) => cells.map((cell) => cell.textContent));
  assert.equal(results.length, 3);
  for (const result of results) {
    assert.match(result, /^(build error|error): \S/, "the overview says why");
  }
  assert.deepEqual(await overflowing(page), []);
  await page.close();
});

test("grade CLASS: every image loads and nothing runs off the page", async () => {
  const long = "a-student-whose-folder-name-goes-on-and-on-without-a-single-space-to-break-it-".repeat(3);
  for (const student of ["ann", long]) mkdirSync(join(dir, "renders", student), { recursive: true });
  for (const chapter of [1, 2]) {
    execFileSync(RAYLAB, ["render", "--chapter", String(chapter), "--width", "160", "--height", "120", "-o", join(dir, "renders", "ann", `chapter-${chapter}.png`)], { stdio: "ignore" });
  }
  // Chapter 1's image handed in for chapter 2: a failing chapter, whose
  // figures the report inlines.
  copyFileSync(join(dir, "renders", "ann", "chapter-1.png"), join(dir, "renders", long, "chapter-1.png"));
  copyFileSync(join(dir, "renders", "ann", "chapter-1.png"), join(dir, "renders", long, "chapter-2.png"));
  grade(["renders"]);
  const page = await open("renders/report.html", "report-renders");
  const images = await page.$$eval("img", (all) => all.map((image) => ({ loaded: image.complete && image.naturalWidth > 0, alt: image.alt })));
  assert.ok(images.length >= 3, `the failing chapter's figures are in the report: ${images.length} images`);
  assert.deepEqual(images.filter((image) => !image.loaded), [], "every image loads");
  assert.deepEqual(await overflowing(page), []);
  await page.close();
});
