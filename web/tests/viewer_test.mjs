#!/usr/bin/env node
// The viewer page's browser test: starts `hoidslam run … --view`, opens the page in headless Chromium and checks
// what it shows against the files the run wrote (docs/viewer.md, "The browser test"); or opens a run report and
// checks the same page inlined in it.
//
//   node viewer_test.mjs --hoidslam BIN --out RUN_FOLDER [--close-tab-midway] [--live-dense] [--playwright DIR]
//                        [--chromium PATH] [--screenshot PNG] [--timeout SECONDS] -- <hoidslam run arguments>
//   node viewer_test.mjs --report REPORT_HTML --out RUN_FOLDER [--playwright DIR] [--chromium PATH]
//                        [--screenshot PNG] [--timeout SECONDS]
//
// Default: the run keeps serving once finished (--view-keep); the page must log no error or warning and ask for
// nothing outside 127.0.0.1, and its numbers must match map.ply, keyframes.txt and frames.jsonl; the screenshot
// must not be blank; SIGINT must end the run with status 0.
// --close-tab-midway: the page is closed while the run goes, and the run must finish and exit 0 by itself.
// --live-dense (a run with --dense): before the run finished, the page must have drawn more than one dense map: the
// live preview as it grew, then the final map.
// --report: the report of the run folder, opened from its file, must ask for nothing at all and log no error or
// warning; its map must show the points of map.ply and the keyframes of keyframes.txt, and must not be blank.
// Either way, when the run folder has a mesh.ply (a run with --dense), the page must draw a dense map of at most
// REPORT_DENSE_TRIANGLES triangles (in a report, as many as it embeds) that its legend's box hides and shows again;
// without one, none.
// playwright-core comes from --playwright DIR or $HOIDSLAM_PLAYWRIGHT (the build's web-node/node_modules/playwright-core).
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const USAGE = 'usage: node viewer_test.mjs --hoidslam BIN --out RUN_FOLDER [--close-tab-midway] [--playwright DIR] ' +
  '[--live-dense] [--chromium PATH] [--screenshot PNG] [--timeout SECONDS] -- <hoidslam run arguments>\n' +
  '   or: node viewer_test.mjs --report REPORT_HTML --out RUN_FOLDER [--playwright DIR] [--chromium PATH] ' +
  '[--screenshot PNG] [--timeout SECONDS]';
const POLL_MS = 250;
const SETTLE_MS = 1500; // the map counts must stay the same this long after the run finished
const UPDATES_BEFORE_CLOSING = 5;
const REPORT_DENSE_TRIANGLES = 100000; // the budget of the dense map the run shows (report::kReportDenseTriangles)
// The emulated GPU driver's note on its own speed (see launchBrowser): the browser's, not the page's.
const DRIVER_PERFORMANCE_NOTE = /^\[\.WebGL-[0-9a-fx]+\]GL Driver Message \(OpenGL, Performance, .*\): GPU stall due to ReadPixels/;

const failures = [];
const fail = (message) => failures.push(message);
let run = null;
let browser = null;
let currentStep = 'starting'; // what the test was doing, for the message when it times out
let tested = 'viewer'; // or 'report', for the closing line

function parseArguments(argv) {
  const split = argv.indexOf('--');
  const own = split < 0 ? argv : argv.slice(0, split);
  const options = {
    hoidslam: null, report: null, out: null, closeTabMidway: false, liveDense: false, timeoutSeconds: 120,
    playwright: process.env.HOIDSLAM_PLAYWRIGHT ?? null, chromium: '/usr/bin/chromium', screenshot: null,
    runArguments: split < 0 ? [] : argv.slice(split + 1),
  };
  const valued = { '--hoidslam': 'hoidslam', '--report': 'report', '--out': 'out', '--playwright': 'playwright',
    '--chromium': 'chromium', '--screenshot': 'screenshot', '--timeout': 'timeoutSeconds' };
  for (let i = 0; i < own.length; i += 1) {
    if (own[i] === '--close-tab-midway') options.closeTabMidway = true;
    else if (own[i] === '--live-dense') options.liveDense = true;
    else if (valued[own[i]] && i + 1 < own.length) options[valued[own[i]]] = own[++i];
    else throw new Error(`unknown argument ${own[i]}\n${USAGE}`);
  }
  const required = [['--out', options.out], ['--playwright', options.playwright]];
  if (!options.report) required.push(['--hoidslam', options.hoidslam]);
  for (const [name, value] of required) {
    if (!value) throw new Error(`${name} is missing${name === '--playwright' ? ' (or $HOIDSLAM_PLAYWRIGHT)' : ''}\n${USAGE}`);
  }
  options.timeoutSeconds = Number(options.timeoutSeconds);
  options.screenshot ??= path.join(options.out, options.report ? 'report-map.png' : 'viewer.png');
  return options;
}

/** Starts the run and resolves with the viewer's address once the run prints it on standard error. */
function startRun(options) {
  const args = ['run', ...options.runArguments, '--out', options.out, '--view', '--view-port', '0'];
  if (!options.closeTabMidway) args.push('--view-keep');
  console.log(`starting ${options.hoidslam} ${args.join(' ')}`);
  currentStep = 'waiting for the run to print "viewer: http://…"';
  run = spawn(options.hoidslam, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  run.output = '';
  run.exited = new Promise((resolve) => run.on('exit', (code, signal) => resolve({ code, signal })));
  run.stdout.on('data', (chunk) => { run.output += chunk; });
  return new Promise((resolve, reject) => {
    run.stderr.on('data', (chunk) => {
      run.output += chunk;
      const address = /viewer: (http:\/\/\S+)/.exec(run.output);
      if (address) resolve(address[1]);
    });
    run.exited.then(({ code, signal }) => reject(new Error(`the run exited (${signal ?? `status ${code}`}) before ` +
      'printing "viewer: http://…"')));
  });
}

async function launchBrowser(options) {
  currentStep = 'starting Chromium';
  const { chromium } = createRequire(import.meta.url)(path.resolve(options.playwright));
  // A test machine has no GPU: WebGL runs on ANGLE's SwiftShader, on the CPU, and the page is composited in software
  // (through the GPU process emulated on the CPU, a 2-core machine composits some 7 frames a second; in software
  // over 20). The emulated driver then says "GPU stall due to ReadPixels" on the console when the WebGL canvas is
  // composited (DRIVER_PERFORMANCE_NOTE below).
  const args = ['--use-angle=swiftshader', '--disable-gpu-compositing'];
  if (process.getuid?.() === 0) args.push('--no-sandbox'); // Chromium's sandbox refuses to run as root
  browser = await chromium.launch({ executablePath: options.chromium, headless: true, args, timeout: 30_000 });
  return browser;
}

/**
 * Opens the page, noting every console error or warning and every request `allowed` (given the request's URL)
 * refuses; `allowedWhat` says what is allowed, for the message.
 */
async function openPage(address, allowed, allowedWhat) {
  currentStep = `opening ${address}`;
  const page = await browser.newPage({ viewport: { width: 1400, height: 850 } });
  page.problems = [];
  page.on('console', (message) => {
    if (message.type() === 'warning' && DRIVER_PERFORMANCE_NOTE.test(message.text())) return;
    if (['error', 'warning'].includes(message.type())) page.problems.push(`console ${message.type()}: ${message.text()}`);
  });
  page.on('pageerror', (error) => page.problems.push(`uncaught exception: ${error.message}`));
  page.on('request', (request) => {
    const url = new URL(request.url());
    if (!['data:', 'blob:'].includes(url.protocol) && !allowed(url)) {
      page.problems.push(`request for ${request.url()}, ${allowedWhat}`);
    }
  });
  await page.goto(address, { timeout: 30_000 });
  return page;
}

/** The page's stat values (window.hoidslamViewer mirrors the stat-… elements: the elements are what is read). */
function readStats(page) {
  return page.evaluate(() => Object.fromEntries(
    [...document.querySelectorAll('[id^="stat-"]')].map((node) => [node.id.slice(5), node.dataset.value])));
}

async function waitFor(description, condition, timeoutMs) {
  currentStep = `waiting for ${description}`;
  const deadline = Date.now() + timeoutMs;
  for (;;) {
    const value = await condition();
    if (value) return value;
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${description}`);
    await new Promise((resolve) => setTimeout(resolve, POLL_MS));
  }
}

/**
 * Waits for the run to finish, measuring how many frames a second the page drew meanwhile; returns the triangle
 * counts of the dense maps it was seen to draw before.
 */
async function waitForFinish(page, timeoutMs) {
  let firstDrawn = null;
  const denseWhileRunning = new Set();
  const last = await waitFor('stat-run to read "finished"', async () => {
    const stats = await readStats(page);
    if (!firstDrawn && Number(stats.updates) > 0) firstDrawn = { time: Date.now(), updates: Number(stats.updates) };
    if (stats.run !== 'finished' && Number(stats.dense) > 0) denseWhileRunning.add(Number(stats.dense));
    return stats.run === 'finished' && { time: Date.now(), updates: Number(stats.updates) };
  }, timeoutMs);
  if (firstDrawn && last.time > firstDrawn.time) {
    const rate = (last.updates - firstDrawn.updates) / ((last.time - firstDrawn.time) / 1000);
    console.log(`the page drew ${rate.toFixed(1)} frame updates a second while the run went ` +
      `(${last.updates} in all)`);
  }
  return [...denseWhileRunning];
}

/** The stats once the map counts and the frame shown have stayed the same for SETTLE_MS. */
async function waitForSettledStats(page, timeoutMs) {
  let previous = null;
  let since = Date.now();
  return waitFor('the map to settle', async () => {
    const stats = await readStats(page);
    const key = `${stats.points}/${stats.keyframes}/${stats.frame}/${stats.dense}`;
    if (key !== previous) {
      previous = key;
      since = Date.now();
    }
    return Date.now() - since >= SETTLE_MS && stats;
  }, timeoutMs);
}

/** The count of an element (vertex, face) a PLY file's header declares. */
function plyElementCount(file, element) {
  const bytes = fs.readFileSync(file);
  const headerEnd = bytes.indexOf('end_header');
  const header = bytes.subarray(0, Math.max(headerEnd, 0)).toString('latin1');
  const count = new RegExp(`element ${element} (\\d+)`).exec(header);
  if (!count) throw new Error(`${file} has no "element ${element} N" in its header`);
  return Number(count[1]);
}

function trajectoryLineCount(file) {
  return fs.readFileSync(file, 'utf8').split('\n').filter((line) => line.trim() && !line.startsWith('#')).length;
}

function frameLogLine(file, frameIndex) {
  for (const line of fs.readFileSync(file, 'utf8').split('\n')) {
    if (!line.trim()) continue;
    const entry = JSON.parse(line);
    if (entry.frame === frameIndex) return entry;
  }
  return null;
}

/**
 * How much a PNG shows: it is decoded in a blank page's canvas; returns its count of distinct colours and the
 * share of pixels that differ from its most common colour (the background).
 */
async function pictureContent(png) {
  const page = await browser.newPage();
  try {
    return await page.evaluate(async (source) => {
      const image = new Image();
      image.src = source;
      await image.decode();
      const canvas = document.createElement('canvas');
      canvas.width = image.naturalWidth;
      canvas.height = image.naturalHeight;
      const context = canvas.getContext('2d');
      context.drawImage(image, 0, 0);
      const pixels = new Uint32Array(context.getImageData(0, 0, canvas.width, canvas.height).data.buffer);
      const counts = new Map();
      for (const pixel of pixels) counts.set(pixel, (counts.get(pixel) ?? 0) + 1);
      const background = Math.max(...counts.values());
      return { colours: counts.size, foreground: 1 - background / pixels.length };
    }, `data:image/png;base64,${png.toString('base64')}`);
  } finally {
    await page.close();
  }
}

function checkEqual(what, shown, expected) {
  if (String(shown) !== String(expected)) fail(`${what}: the page shows ${shown}, expected ${expected}`);
  else console.log(`ok: ${what} = ${expected}`);
}

/** stat-points and stat-keyframes against the main map the run wrote into `folder`. */
function checkMapCounts(stats, folder) {
  checkEqual('stat-points (main map) against map.ply', stats.points,
    plyElementCount(path.join(folder, 'map.ply'), 'vertex'));
  checkEqual('stat-keyframes (main map) against keyframes.txt', stats.keyframes,
    trajectoryLineCount(path.join(folder, 'keyframes.txt')));
}

/**
 * The dense map against the run folder's mesh.ply: none without one; with one, drawn (as many triangles as the
 * report embeds, when it does), within the budget and mesh.ply's own count, and hidden and shown by its legend box.
 */
async function checkDenseMap(page, stats, folder) {
  const mesh = path.join(folder, 'mesh.ply');
  if (!fs.existsSync(mesh)) {
    checkEqual('stat-dense without mesh.ply', stats.dense, '');
    return;
  }
  const shown = Number(stats.dense);
  const limit = Math.min(REPORT_DENSE_TRIANGLES, plyElementCount(mesh, 'face'));
  if (!(shown > 0 && shown <= limit)) fail(`stat-dense is ${stats.dense}: expected a dense map of 1 to ${limit} triangles`);
  else console.log(`ok: stat-dense = ${shown} triangles drawn (mesh.ply has ${plyElementCount(mesh, 'face')})`);
  const embedded = await page.evaluate(() => {
    const data = document.getElementById('hoidslam-data');
    return data ? JSON.parse(data.textContent).dense?.triangles ?? null : null;
  });
  if (embedded !== null) checkEqual('stat-dense against the embedded dense map', stats.dense, embedded);
  currentStep = 'toggling the dense map';
  const toggle = page.locator('#dense-map-toggle');
  await toggle.uncheck();
  await waitFor('stat-dense to read 0 with the dense map hidden', async () => (await readStats(page)).dense === '0',
    10_000);
  await toggle.check();
  await waitFor('stat-dense to come back with the dense map shown',
    async () => (await readStats(page)).dense === String(shown), 10_000);
  console.log('ok: the legend\'s box hides and shows the dense map');
}

/** Takes the screenshot of `shown` (the page, or a locator of its part) and fails when it or the map is blank. */
async function checkPictures(page, shown, screenshotPath) {
  currentStep = 'taking screenshots';
  const screenshot = await shown.screenshot({ path: screenshotPath, timeout: 30_000 });
  const whole = await pictureContent(screenshot);
  const map = await pictureContent(await page.locator('.map-panel').screenshot({ timeout: 30_000 }));
  console.log(`screenshot ${screenshotPath}: ${whole.colours} colours; the map panel has ` +
    `${(100 * map.foreground).toFixed(1)} % of its pixels drawn`);
  if (whole.colours < 100) fail(`the screenshot ${screenshotPath} is blank (${whole.colours} colours)`);
  if (map.foreground < 0.002) fail(`the map panel is blank (${(100 * map.foreground).toFixed(2)} % of its pixels drawn)`);
}

async function checkFinishedRun(page, options, deadline) {
  const denseWhileRunning = await waitForFinish(page, deadline - Date.now());
  if (options.liveDense) {
    const counts = denseWhileRunning.join(', ') || 'none';
    if (denseWhileRunning.length > 1) console.log(`ok: the page drew dense maps of ${counts} triangles while the run went`);
    else fail(`the page drew dense maps of ${counts} triangles while the run went: no live preview (--live-dense)`);
  }
  const stats = await waitForSettledStats(page, deadline - Date.now());
  checkMapCounts(stats, options.out);
  const entry = frameLogLine(path.join(options.out, 'frames.jsonl'), Number(stats.frame));
  if (!entry) {
    fail(`frames.jsonl has no line for the frame the page shows (stat-frame ${stats.frame})`);
  } else {
    checkEqual(`stat-kept of frame ${stats.frame} against frames.jsonl`, stats.kept, entry.features.kept);
    checkEqual(`stat-dropped of frame ${stats.frame} against frames.jsonl`, stats.dropped, entry.features.dropped);
  }
  if (!(Number(stats.updates) > 0)) fail(`stat-updates is ${stats.updates}: the page drew no frame`);
  await checkDenseMap(page, stats, options.out);

  failures.push(...page.problems);
  page.problems = []; // what the page logs once the run is interrupted is not the page's doing
  await checkPictures(page, page, options.screenshot);

  run.kill('SIGINT');
  const exit = await withTimeout(run.exited, 30_000, 'the run to exit after SIGINT');
  if (exit.code !== 0) fail(`the run exited with ${exit.signal ?? `status ${exit.code}`} after SIGINT, expected 0`);
}

async function checkTabClosedMidway(page, options, deadline) {
  await waitFor(`${UPDATES_BEFORE_CLOSING} frame updates`,
    async () => Number((await readStats(page)).updates) >= UPDATES_BEFORE_CLOSING, deadline - Date.now());
  failures.push(...page.problems);
  await page.close();
  await browser.close();
  browser = null;
  console.log('closed the page and the browser while the run goes');
  const exit = await withTimeout(run.exited, deadline - Date.now(), 'the run to exit by itself');
  if (exit.code !== 0) fail(`the run exited with ${exit.signal ?? `status ${exit.code}`}, expected 0`);
  for (const file of ['summary.json', 'trajectory.txt']) {
    if (!fs.existsSync(path.join(options.out, file))) fail(`the run did not write ${file}`);
  }
}

function withTimeout(promise, timeoutMs, description) {
  currentStep = `waiting for ${description}`;
  let timer;
  const timeout = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Error(`timed out waiting for ${description}`)), Math.max(timeoutMs, 0));
  });
  return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
}

async function cleanUp() {
  if (run && run.exitCode === null && run.signalCode === null) run.kill('SIGKILL');
  if (browser) await withTimeout(browser.close(), 10_000, 'the browser to close').catch(() => {});
}

/** The report's map section: the page inlined in a file, with the run's map as its data and no run to talk to. */
async function checkReport(options, deadline) {
  await launchBrowser(options);
  const address = pathToFileURL(path.resolve(options.report)).href;
  const page = await openPage(address, (url) => url.href === address, 'a report must ask for nothing');
  const stats = await waitForSettledStats(page, deadline - Date.now());
  checkMapCounts(stats, options.out);
  checkEqual('stat-run', stats.run, 'finished');
  await checkDenseMap(page, stats, options.out);
  await checkPictures(page, page.locator('#hoidslam-viewer'), options.screenshot);
  failures.push(...page.problems);
}

async function test(options, deadline) {
  if (options.report) {
    await checkReport(options, deadline);
    return;
  }
  const address = await startRun(options);
  console.log(`viewer at ${address}`);
  await launchBrowser(options);
  const page = await openPage(address, (url) => url.hostname === '127.0.0.1', 'outside 127.0.0.1');
  if (options.closeTabMidway) await checkTabClosedMidway(page, options, deadline);
  else await checkFinishedRun(page, options, deadline);
}

async function main() {
  const options = parseArguments(process.argv.slice(2));
  if (options.report) tested = 'report';
  // A hang anywhere fails the test: the whole test has one deadline, and says what it was waiting for.
  const deadline = Date.now() + options.timeoutSeconds * 1000;
  let timer;
  const timedOut = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Error(`timed out after ${options.timeoutSeconds} s ${currentStep}`)),
      options.timeoutSeconds * 1000);
  });
  try {
    await Promise.race([test(options, deadline), timedOut]);
  } finally {
    clearTimeout(timer);
  }
}

try {
  await main();
} catch (error) {
  fail(error.message);
} finally {
  await cleanUp();
}
if (failures.length > 0) {
  for (const failure of failures) console.log(`FAILED: ${failure}`);
  if (run?.output) console.log(`the run's output:\n${run.output.trimEnd()}`);
  process.exit(1);
}
console.log(`${tested} test passed`);
process.exit(0);
