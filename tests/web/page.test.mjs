// The web page in a real browser: Debian's chromium, headless, driven by playwright-core (web/node_modules; it
// never downloads a browser). Starts the real `wish serve` (WISH_BIN, --port 0) on the bundled default model, loads
// GET /, uploads meshes through the file picker and checks what a user sees against what the API returns.
// Screenshots of each view go to WISH_SCREENSHOT_DIR (ctest: <build>/web-screenshots).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { copyFileSync, existsSync, mkdirSync, mkdtempSync, openSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const source = process.env.WISH_SOURCE_DIR || join(here, '..', '..');
const wishBin = process.env.WISH_BIN || join(source, 'build', 'release', 'cli', 'wish');
const chromiumPath = process.env.WISH_CHROMIUM || '/usr/bin/chromium';
const shotDir = process.env.WISH_SCREENSHOT_DIR || join(source, 'build', 'web-screenshots');
const meshes = join(source, 'data', 'meshes');
const missing = !existsSync(wishBin) ? `wish binary not found at ${wishBin}`
  : !existsSync(chromiumPath) ? `chromium not found at ${chromiumPath} (scripts/install-deps.sh --test installs it)`
  : !existsSync(join(source, 'web', 'node_modules', 'playwright-core')) ? 'web/node_modules missing: run npm ci in web/'
  : null;

const work = mkdtempSync(join(tmpdir(), 'wish-web-test-'));
const servers = [];
let browser = null;

// A `wish serve` on a free port; resolves with its base URL once it logs "listening on". modelFiles: more files
// for the models directory ({name: text}) besides default.json.
async function startServer(extraArgs = [], modelFiles = {}) {
  const models = join(work, `models-${servers.length}`);
  mkdirSync(models);
  copyFileSync(join(source, 'data', 'models', 'default.json'), join(models, 'default.json'));
  for (const [name, text] of Object.entries(modelFiles)) writeFileSync(join(models, name), text);
  const logPath = join(work, `server-${servers.length}.log`);
  const log = openSync(logPath, 'w');
  const proc = spawn(wishBin, ['serve', '--models', models, '--host', '127.0.0.1', '--port', '0', '--workers', '2',
                               ...extraArgs], { stdio: ['ignore', log, log] });
  servers.push(proc);
  for (let i = 0; i < 600; ++i) {  // at most 30 s
    const m = /listening on http:\/\/127\.0\.0\.1:(\d+)/.exec(readFileSync(logPath, 'utf8'));
    if (m) return `http://127.0.0.1:${m[1]}`;
    if (proc.exitCode !== null) break;
    await new Promise((r) => setTimeout(r, 50));
  }
  throw new Error(`server did not start: ${readFileSync(logPath, 'utf8').slice(-2000)}`);
}

async function newPage() {
  const page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
  const problems = [];
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  // Chromium logs every 4xx response as a console error; those are the API's answers the page shows, not faults.
  page.on('console', (m) => {
    if (m.type() === 'error' && !/status of 4\d\d/.test(m.text())) problems.push(`console: ${m.text()}`);
  });
  // Offline: any request that leaves the service's origin is a failure (the page must not use a CDN).
  await page.route('**/*', (route) => {
    const url = new URL(route.request().url());
    if (url.hostname !== '127.0.0.1') { problems.push(`external request: ${url}`); return route.abort(); }
    return route.continue();
  });
  return { page, problems };
}

// Pixels of a view's WebGL canvas (read back through a 2-D canvas): the fraction that is not the white background
// and a checksum, so that "draws something" and "changed" are both checkable.
function canvasStats(page, selector) {
  return page.evaluate((sel) => {
    const gl = document.querySelector(`${sel} canvas`);
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    let drawn = 0, sum = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (d[i] < 250 || d[i + 1] < 250 || d[i + 2] < 250) drawn++;
      sum = (sum * 31 + d[i] * 7 + d[i + 1] * 3 + d[i + 2]) % 1000000007;
    }
    return { drawn: drawn / (d.length / 4), sum, width: c.width, height: c.height };
  }, selector);
}

async function postRaw(base, path, bytes) {
  const r = await fetch(base + path, { method: 'POST', body: bytes, headers: { 'Content-Type': 'application/octet-stream' } });
  return { status: r.status, body: await r.json() };
}

const BROKEN = 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n';  // truncated: the 4th vertex and both faces are missing

before(async () => {
  if (missing) return;
  mkdirSync(shotDir, { recursive: true });
  const { chromium } = await import(join(source, 'web', 'node_modules', 'playwright-core', 'index.mjs'));
  browser = await chromium.launchPersistentContext(join(work, 'profile'), {
    executablePath: chromiumPath, headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
           '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
});

after(async () => {
  if (browser) await browser.close();
  for (const p of servers) p.kill('SIGTERM');
  await Promise.all(servers.map((p) => (p.exitCode !== null ? null : new Promise((r) => p.once('exit', r)))));
  rmSync(work, { recursive: true, force: true });
});

test('upload, views, quality table, slider, errors and batch table', { skip: missing || false, timeout: 300000 }, async () => {
  const base = await startServer();
  const { page, problems } = await newPage();
  await page.goto(base + '/');
  await page.waitForFunction(() => document.querySelectorAll('#model-select option').length > 0, null, { timeout: 30000 });

  const brokenPath = join(work, 'broken.off');
  writeFileSync(brokenPath, BROKEN);
  const files = [join(meshes, 'celegans_cell.obj'), brokenPath, join(meshes, 'eight.off'), join(meshes, 'ellipsoid.off')];
  await page.setInputFiles('#file-input', files);
  await page.waitForFunction((n) => {
    const cells = [...document.querySelectorAll('#batch-table tbody td[data-status]')];
    return cells.length === n && cells.every((c) => c.dataset.status === 'done' || c.dataset.status === 'error');
  }, files.length, { timeout: 240000 });

  // The batch table lists every file.
  const listed = await page.$$eval('#batch-table tbody tr', (rows) => rows.map((r) => r.dataset.file));
  assert.deepEqual(listed.sort(), ['broken.off', 'celegans_cell.obj', 'eight.off', 'ellipsoid.off']);

  // Broken files show the API's own error code (asked for independently here).
  for (const name of ['broken.off', 'eight.off']) {
    const api = await postRaw(base, '/v1/classify', readFileSync(name === 'broken.off' ? brokenPath : join(meshes, name)));
    assert.ok(api.status >= 400, `${name}: ${api.status}`);
    const code = await page.$eval(`#batch-table tr[data-file="${name}"] td[data-status]`, (td) => td.dataset.code);
    assert.equal(code, api.body.error.code, name);
    const text = await page.$eval(`#batch-table tr[data-file="${name}"] td[data-status]`, (td) => td.textContent);
    assert.ok(text.includes(String(api.status)) && text.includes(api.body.error.code), text);
  }
  await page.click('#batch-table tr[data-file="eight.off"]');
  const detailError = await page.textContent('#detail-error');
  assert.match(detailError, /HTTP 422 genus_nonzero/);

  // Open the C. elegans cell: the 3-D views draw.
  await page.click('#batch-table tr[data-file="celegans_cell.obj"]');
  await page.waitForSelector('#input-view canvas');
  await page.waitForTimeout(300);
  const views = ['#input-view', '#sphere-view', '#recon-view'];
  for (const v of views) {
    const s = await canvasStats(page, v);
    assert.ok(s.width > 100 && s.height > 100, `${v} size ${s.width}x${s.height}`);
    assert.ok(s.drawn > 0.03 && s.drawn < 0.95, `${v}: ${(100 * s.drawn).toFixed(1)} % of the pixels drawn`);
  }

  // Rotating the input view (a mouse drag: OrbitControls) changes its pixels.
  const before = await canvasStats(page, '#input-view');
  const box = await page.locator('#input-view canvas').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 40, { steps: 8 });
  await page.mouse.up();
  const rotated = await canvasStats(page, '#input-view');
  assert.notEqual(rotated.sum, before.sum, 'the input view did not change when rotated');
  assert.ok(rotated.drawn > 0.03);

  // Colouring by a per-face field changes the picture too.
  await page.selectOption('#input-field', 'conformal');
  const coloured = await canvasStats(page, '#input-view');
  assert.notEqual(coloured.sum, rotated.sum);

  // The quality table shows the numbers of the API's JSON for this mesh (requested independently; the map is
  // deterministic), as printed: 6 significant digits.
  const api = await postRaw(base, '/v1/classify?include=quality', readFileSync(join(meshes, 'celegans_cell.obj')));
  assert.equal(api.status, 200);
  const cells = await page.$$eval('#quality-table td[data-q]', (tds) => Object.fromEntries(tds.map((td) => [td.dataset.q, td.textContent])));
  const q = api.body.map.quality;
  for (const key of ['flipped_faces', 'degenerate_faces', 'degree', 'conformal_mean', 'conformal_p99', 'conformal_max',
                     'area_distortion', 'roundness']) {
    const shown = Number(cells[key]);
    assert.ok(Math.abs(shown - q[key]) <= 5e-6 * Math.abs(q[key]) + 1e-300, `${key}: shown ${cells[key]}, JSON ${q[key]}`);
  }
  assert.equal(cells.method, api.body.map.method);
  assert.equal(cells.status, api.body.map.status);
  const label = await page.textContent('#predicted-label');
  assert.equal(label, api.body.prediction.label);

  // The spectrum shows one dashed class-mean line per class of the model, each the exp of the model's stored
  // mean ln xi(l) (GET /v1/models, training_summary.class_spectra), truncated at the shape's Lmax.
  const models = await (await fetch(`${base}/v1/models`)).json();
  const model = models.models.find((m) => m.name === api.body.prediction.model.name);
  const spectra = model.training_summary.class_spectra;
  assert.equal(spectra.length, model.classes.length, 'the default model carries a spectrum per class');
  const drawn = await page.$$eval('#spectrum polyline[data-kind="class-mean"]',
                                  (ls) => ls.map((l) => JSON.parse(l.dataset.values)));
  assert.equal(drawn.length, spectra.length);
  drawn.forEach((values, i) => {
    const expected = spectra[i].log_xi_mean.slice(0, api.body.descriptor.lmax).map(Math.exp);
    assert.equal(values.length, expected.length);
    values.forEach((v, k) => assert.ok(Math.abs(v - expected[k]) <= 1e-9 * expected[k], `class ${i} l=${k + 1}`));
  });

  // The reconstruction at Lmax, evaluated in the browser from the coefficients, reproduces the service's fit error
  // (mean |x - x_L| at the input vertices): the page's SH conventions are the service's.
  const lmax = api.body.descriptor.lmax;
  assert.equal(await page.getAttribute('#degree-slider', 'max'), String(lmax));
  const meanAtLmax = Number(await page.textContent('#recon-stats .recon-mean'));
  const serviceMean = api.body.descriptor.fit_error.mean;
  assert.ok(Math.abs(meanAtLmax - serviceMean) <= 1e-5 * serviceMean, `browser ${meanAtLmax}, service ${serviceMean}`);

  await page.locator('#input-view').screenshot({ path: join(shotDir, 'input-mesh.png') });
  await page.locator('#sphere-view').screenshot({ path: join(shotDir, 'sphere-map.png') });
  await page.locator('#recon-view').screenshot({ path: join(shotDir, 'reconstruction-lmax.png') });
  await page.locator('#spectrum').screenshot({ path: join(shotDir, 'spectrum.png') });
  await page.locator('#prediction').screenshot({ path: join(shotDir, 'prediction.png') });

  // The slider changes the reconstruction: degree 1 keeps the first-order terms only (an ellipsoid).
  const reconLmax = await canvasStats(page, '#recon-view');
  await page.$eval('#degree-slider', (s) => { s.value = '1'; s.dispatchEvent(new Event('input')); });
  const reconL1 = await canvasStats(page, '#recon-view');
  assert.notEqual(reconL1.sum, reconLmax.sum, 'the reconstruction did not change with the degree');
  assert.ok(reconL1.drawn > 0.03);
  const meanAtL1 = Number(await page.textContent('#recon-stats .recon-mean'));
  assert.ok(meanAtL1 > meanAtLmax, `fit error at L=1 (${meanAtL1}) should exceed the one at Lmax (${meanAtLmax})`);
  await page.locator('#recon-view').screenshot({ path: join(shotDir, 'reconstruction-l1.png') });

  // Sorting by file name orders the rows.
  await page.click('#batch-table th[data-key="file"]');
  const sorted = await page.$$eval('#batch-table tbody tr', (rows) => rows.map((r) => r.dataset.file));
  assert.deepEqual(sorted, ['broken.off', 'celegans_cell.obj', 'eight.off', 'ellipsoid.off']);
  await page.click('#batch-table th[data-key="file"]');
  const reversed = await page.$$eval('#batch-table tbody tr', (rows) => rows.map((r) => r.dataset.file));
  assert.deepEqual(reversed, ['ellipsoid.off', 'eight.off', 'celegans_cell.obj', 'broken.off']);

  // The CSV download has one row per file.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download-csv')]);
  const csv = readFileSync(await download.path(), 'utf8').trim().split('\n');
  assert.equal(csv.length, 1 + files.length);
  assert.ok(csv.some((line) => line.startsWith('eight.off,422,genus_nonzero')), csv.join('\n'));

  await page.screenshot({ path: join(shotDir, 'page.png'), fullPage: true });
  assert.deepEqual(problems, []);
  await page.close();
});

test('with a token, the page asks for it and sends it', { skip: missing || false, timeout: 120000 }, async () => {
  const base = await startServer(['--auth-token', 'page-test-token']);
  const { page, problems } = await newPage();
  await page.goto(base + '/');
  await page.waitForSelector('#token-dialog[open]', { timeout: 30000 });
  await page.fill('#token-input', 'page-test-token');
  await page.click('#token-submit');
  await page.waitForFunction(() => document.querySelectorAll('#model-select option').length > 0, null, { timeout: 30000 });
  const status = await page.textContent('#service-status');
  assert.match(status, /1 model\(s\) loaded/);
  // Nothing was stored by the page.
  const stored = await page.evaluate(() => [localStorage.length, sessionStorage.length, document.cookie]);
  assert.deepEqual(stored, [0, 0, '']);
  assert.deepEqual(problems, []);
  await page.close();
});

test('describe with a chosen Lmax and method', { skip: missing || false, timeout: 120000 }, async () => {
  const base = await startServer();
  const { page, problems } = await newPage();
  await page.goto(base + '/');
  await page.waitForFunction(() => document.querySelectorAll('#model-select option').length > 0, null, { timeout: 30000 });
  await page.selectOption('#operation', 'describe');
  assert.ok(await page.isVisible('#lmax-input'));
  await page.fill('#lmax-input', '8');
  // The choices are the served contract's MapMethod schema (generated from core's table), after "default".
  const contract = JSON.parse(readFileSync(join(source, 'proto', 'openapi.json'), 'utf8'));
  const methods = contract.components.schemas.MapMethod.enum;
  await page.waitForFunction((n) => document.querySelectorAll('#method-select option').length === n + 1,
                             methods.length, { timeout: 30000 });
  assert.deepEqual(await page.$$eval('#method-select option', (os) => os.map((o) => o.value)), ['', ...methods]);
  await page.selectOption('#method-select', 'cmcf');
  await page.setInputFiles('#file-input', [join(meshes, 'ellipsoid.off')]);
  await page.waitForSelector('#batch-table td[data-status="done"]', { timeout: 60000 });
  await page.click('#batch-table tr[data-file="ellipsoid.off"]');
  assert.equal(await page.getAttribute('#degree-slider', 'max'), '8');
  const state = await page.evaluate(() => {
    const r = window.wishPage.state.items[0].result;
    return { lmax: r.descriptor.lmax, method: r.descriptor.settings.method, prediction: 'prediction' in r };
  });
  assert.deepEqual(state, { lmax: 8, method: 'cmcf', prediction: false });
  assert.match(await page.textContent('#prediction'), /no prediction/);
  // 8 degrees: the spectrum shows l = 1..8.
  assert.equal(await page.locator('#spectrum circle').count(), 8);
  assert.deepEqual(problems, []);
  await page.close();
});

test('Models: metadata and the training report (heat map, confusion matrix, per-class scores)',
     { skip: missing || false, timeout: 120000 }, async () => {
  const report = readFileSync(join(source, 'data', 'models', 'default-report.json'), 'utf8');
  const base = await startServer([], { 'default-report.json': report });
  const name = (await (await fetch(`${base}/v1/models`)).json()).default;  // the model's name (not its file's)
  const card = `.model[data-model="${name}"]`;
  const { page, problems } = await newPage();
  await page.goto(base + '/');
  await page.waitForSelector(`${card} .report-box[data-state="shown"]`, { timeout: 30000 });
  const api = await (await fetch(`${base}/v1/models/${encodeURIComponent(name)}/report`)).json();
  assert.deepEqual(api, JSON.parse(report));  // the endpoint serves the file as written

  // The heat map: one cell per (C, gamma), each holding the JSON's mean accuracy, printed to 2 decimals; the
  // best cell outlined; the colours vary with the value (the view draws).
  const cells = await page.$$eval(`${card} svg.heatmap g.cell`, (gs) => gs.map((g) => ({
    row: Number(g.dataset.row), col: Number(g.dataset.col), value: Number(g.dataset.value),
    text: g.querySelector('text').textContent, fill: g.querySelector('rect').getAttribute('fill'),
    best: g.classList.contains('best') })));
  const grid = api.grid;
  assert.equal(cells.length, grid.C.length * grid.gamma.length);
  // A null in the JSON is a cell the early stop did not evaluate: drawn grey with a dash, no number.
  let skipped = 0;
  for (const c of cells) {
    const expected = grid.mean_accuracy[c.row][c.col];
    if (expected === null) {
      skipped += 1;
      assert.ok(Number.isNaN(c.value), `cell ${c.row},${c.col} is skipped but carries a value`);
      assert.equal(c.text, '—', `cell ${c.row},${c.col} text`);
      assert.equal(c.fill, '#eee', `cell ${c.row},${c.col} fill`);
      continue;
    }
    assert.equal(c.value, expected, `cell ${c.row},${c.col}`);
    assert.equal(c.text, expected.toFixed(2), `cell ${c.row},${c.col} text`);
  }
  assert.equal(skipped, grid.mean_accuracy.flat().filter((v) => v === null).length);
  const best = cells.filter((c) => c.best);
  assert.deepEqual(best.map((c) => [grid.C[c.row], grid.gamma[c.col]]), [[grid.best_C, grid.best_gamma]]);
  assert.equal(best[0].value, grid.best_score);
  const distinctValues = new Set(cells.map((c) => c.value)).size;
  assert.ok(distinctValues > 1);
  assert.ok(new Set(cells.map((c) => c.fill)).size > 1, 'every heat-map cell has the same colour');

  // The confusion matrix: every count as in the JSON (rows true, columns predicted).
  const counts = await page.$$eval(`${card} table.confusion td[data-row]`, (tds) => tds.map((td) => [
    Number(td.dataset.row), Number(td.dataset.col), td.textContent]));
  const cm = api.test.confusion_matrix;
  assert.equal(counts.length, cm.length * cm.length);
  for (const [i, j, text] of counts) assert.equal(text, String(cm[i][j]), `confusion ${i},${j}`);

  // Per-class precision / recall / F1 as printed (3 significant digits) and the support exactly.
  const scores = await page.$$eval(`${card} table.per-class td[data-metric]`, (tds) => tds.map((td) => [
    td.dataset.label, td.dataset.metric, td.textContent]));
  assert.equal(scores.length, api.test.per_class.length * 4);
  for (const [label, metric, text] of scores) {
    const want = api.test.per_class.find((c) => c.label === label)[metric];
    if (metric === 'support') assert.equal(text, String(want));
    else assert.ok(Math.abs(Number(text) - want) <= 5e-3 * Math.abs(want) + 1e-12, `${label} ${metric}: ${text} vs ${want}`);
  }
  // The meshes each class kept and lost in training.
  const losses = await page.$$eval(`${card} table.losses td[data-metric]`, (tds) => tds.map((td) => [
    td.dataset.label, td.dataset.metric, td.textContent]));
  assert.equal(losses.length, api.losses.length * 3);
  for (const [label, metric, text] of losses)
    assert.equal(text, String(api.losses.find((c) => c.label === label)[metric]));
  const summary = await page.textContent(`${card} .report-summary`);
  assert.ok(summary.includes(`${api.samples} samples`) && summary.includes(`hold-out ${api.test.accuracy.toPrecision(3)}`), summary);

  await page.locator(card).screenshot({ path: join(shotDir, 'models-report.png') });
  assert.deepEqual(problems, []);
  await page.close();
});

test('Models: a model without a report says so', { skip: missing || false, timeout: 120000 }, async () => {
  const base = await startServer();  // default.json alone, no default-report.json beside it
  const name = (await (await fetch(`${base}/v1/models`)).json()).default;
  const card = `.model[data-model="${name}"]`;
  const { page, problems } = await newPage();
  await page.goto(base + '/');
  await page.waitForSelector(`${card} .report-box[data-state="absent"]`, { timeout: 30000 });
  const api = await fetch(`${base}/v1/models/${encodeURIComponent(name)}/report`);
  assert.equal(api.status, 404);
  const code = (await api.json()).error.code;
  assert.equal(code, 'report_not_found');
  assert.equal(await page.getAttribute(`${card} .report-box`, 'data-code'), code);
  assert.match(await page.textContent(`${card} .report-box`), /No training report/);
  assert.equal(await page.locator('.model svg.heatmap').count(), 0);
  assert.deepEqual(problems, []);
  await page.close();
});

// A uint8 NIfTI-1 of nx × ny × nz voxels (x fastest), voxel (x, y, z) = label(x, y, z); spacing 1 mm.
function niftiBytes(nx, ny, nz, label) {
  const header = Buffer.alloc(352);
  header.writeInt32LE(348, 0);
  [3, nx, ny, nz, 1, 1, 1, 1].forEach((v, k) => header.writeInt16LE(v, 40 + 2 * k));
  header.writeInt16LE(2, 70);  // uint8
  header.writeInt16LE(8, 72);
  [1, 1, 1, 1, 1, 1, 1, 1].forEach((v, k) => header.writeFloatLE(v, 76 + 4 * k));
  header.writeFloatLE(352, 108);
  header.writeFloatLE(1, 112);
  header[123] = 2;
  header.write('n+1\0', 344, 'latin1');
  const data = Buffer.alloc(nx * ny * nz);
  for (let z = 0; z < nz; ++z)
    for (let y = 0; y < ny; ++y)
      for (let x = 0; x < nx; ++x) data[x + nx * (y + ny * z)] = label(x, y, z);
  return Buffer.concat([header, data]);
}

test('Label volume: three slices coloured by class, the legend, a click selects the object', { skip: missing || false, timeout: 300000 }, async () => {
  const base = await startServer();
  const { page, problems } = await newPage();
  await page.goto(base + '/');
  await page.waitForFunction(() => document.querySelectorAll('#model-select option').length > 0, null, { timeout: 30000 });
  const inBall = (x, y, z, c, a) => ((x - c[0]) / a[0]) ** 2 + ((y - c[1]) / a[1]) ** 2 + ((z - c[2]) / a[2]) ** 2 <= 1;
  const bytes = niftiBytes(44, 36, 28, (x, y, z) =>
    inBall(x, y, z, [10, 11, 12], [6, 6, 6]) ? 1 : inBall(x, y, z, [30, 11, 13], [8, 5, 5]) ? 2
      : inBall(x, y, z, [20, 26, 14], [9, 5, 4]) ? 3 : x === 2 && y === 33 && z === 2 ? 9 : 0);
  const path = join(work, 'cells.nii');
  writeFileSync(path, bytes);
  await page.setInputFiles('#vol-input', path);
  await page.waitForFunction(() => window.wishVolume.classMap !== null || !document.querySelector('#vol-error').hidden,
                             null, { timeout: 240000 });
  assert.equal(await page.isHidden('#vol-error'), true, await page.textContent('#vol-error'));

  // What the page shows is what the API returns for the same upload.
  const api = await postRaw(base, '/v1/classify?output=labels', bytes);
  assert.equal(api.status, 200);
  const shown = await page.evaluate(() => window.wishVolume.result);
  assert.deepEqual(shown.objects.map((o) => [o.label_id, o.class_value]), api.body.objects.map((o) => [o.label_id, o.class_value]));
  assert.deepEqual(shown.volume.dropped_objects.map((o) => [o.label_id, o.reason]), [[9, 'speck']]);
  const legend = await page.$$eval('#vol-legend li', (lis) => lis.map((li) => Number(li.dataset.value)));
  assert.deepEqual(legend, api.body.class_map.values.map((v) => v.value));  // K classes, novel, refused

  for (const o of api.body.objects) {
    const [cx, cy, cz] = o.object.centroid.map(Math.round);
    // The xy slice through the object's centroid: the pixel there has the colour of its class value.
    await page.$eval('#vol-z', (s, z) => { s.value = String(z); s.dispatchEvent(new Event('input')); }, cz);
    const rgb = await page.evaluate(([x, y]) => {
      const c = document.querySelector('#vol-xy');
      return [...c.getContext('2d').getImageData(x, c.height - 1 - y, 1, 1).data.slice(0, 3)];
    }, [cx, cy]);
    assert.deepEqual(rgb, api.body.class_map.values.find((v) => v.value === o.class_value).rgb, `object ${o.label_id}`);
    // A click there selects the object's row.
    await page.locator('#vol-xy').scrollIntoViewIfNeeded();
    const box = await page.locator('#vol-xy').boundingBox();
    const size = await page.evaluate(() => [document.querySelector('#vol-xy').width, document.querySelector('#vol-xy').height]);
    await page.mouse.click(box.x + (cx + 0.5) / size[0] * box.width, box.y + (size[1] - 1 - cy + 0.5) / size[1] * box.height);
    assert.equal(await page.getAttribute('#vol-table tbody tr.selected', 'data-id'), String(o.label_id));
    assert.match(await page.textContent('#vol-selected'), new RegExp(`^object ${o.label_id}: `));
  }
  // A click on a row moves the slices to the object.
  await page.click('#vol-table tbody tr[data-id="2"]');
  assert.equal(await page.$eval('#vol-x', (s) => s.value), String(Math.round(api.body.objects[1].object.centroid[0])));
  await page.locator('#volume-panel').screenshot({ path: join(shotDir, 'volume-class-map.png') });
  assert.deepEqual(problems, []);
  await page.close();
});
