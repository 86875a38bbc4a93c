// The WISH page: upload meshes, see each one's input shape, sphere map (coloured by its distortion) with the
// map-quality report, SH reconstruction at a chosen degree, spectrum and prediction; a sortable batch table;
// the loaded models. Talks only to the documented API (api.js).
import { ApiError, getJson, postMesh, setTokenPrompt } from './api.js';
import { cssGradient, diverging, robustRange, viridis } from './colormap.js';
import { renderReport } from './model_report.js';
import { fmt, probabilityBars, spectrumPlot } from './plots.js';
import { evaluateSurface, fitError } from './sh.js';
import { MeshViewer } from './viewer.js';

const $ = (sel) => document.querySelector(sel);
const INCLUDE = 'invariants,quality,coefficients,mesh,sphere,distortion';
const CONCURRENT_UPLOADS = 2;
// Class-mean spectra on the spectrum plot: distinct from the shape's blue and from each other.
const CLASS_COLOURS = ['#dc2626', '#16a34a', '#9333ea', '#ea580c', '#0891b2', '#a16207', '#db2777', '#4b5563'];

const state = { models: [], defaultModel: null, items: [], selected: null, sort: { key: null, dir: 1 }, nextId: 1 };
let viewers = null;

// ------------------------------------------------------------------ auth
setTokenPrompt((retry) => new Promise((resolve) => {
  const dialog = $('#token-dialog');
  $('#token-input').value = '';
  $('#token-input').placeholder = retry ? 'token (the last one was refused)' : 'token';
  dialog.addEventListener('close', () => resolve($('#token-input').value), { once: true });
  dialog.showModal();
}));

// ------------------------------------------------------------------ map methods
// The method choices are the contract's MapMethod schema (generated from core's name table), so a method added to
// core appears here without an edit; the page's own list stays when the contract cannot be read.
async function loadMapMethods() {
  let methods;
  try {
    methods = (await getJson('/openapi.json')).components.schemas.MapMethod.enum;
  } catch {
    return;
  }
  if (!Array.isArray(methods) || methods.length === 0) return;
  const select = $('#method-select');
  for (const o of [...select.options]) if (o.value) o.remove();
  for (const m of methods) {
    const o = document.createElement('option');
    o.value = m; o.textContent = m;
    select.append(o);
  }
}

// ------------------------------------------------------------------ models
async function loadModels() {
  try {
    const list = await getJson('/v1/models');
    state.models = list.models;
    state.defaultModel = list.default;
    $('#service-status').textContent = `${list.models.length} model(s) loaded`;
  } catch (e) {
    $('#service-status').textContent = `models: ${e.code || ''} ${e.message}`;
    state.models = [];
  }
  const select = $('#model-select');
  select.innerHTML = '';
  for (const m of state.models) {
    const o = document.createElement('option');
    o.value = m.name; o.textContent = `${m.name} (v${m.version}, Lmax ${m.descriptor_settings.lmax})`;
    if (m.name === state.defaultModel) o.selected = true;
    select.append(o);
  }
  renderModels();
  updateOptions();
}

function renderModels() {
  const box = $('#models');
  box.innerHTML = '';
  if (!state.models.length) { box.textContent = 'No model is loaded: classify is unavailable, describe works.'; return; }
  for (const m of state.models) {
    const div = document.createElement('div');
    div.className = 'model';
    const ds = m.descriptor_settings, fs = m.feature_spec || {}, ts = m.training_summary || {};
    const rows = [
      ['version', m.version], ['file', m.file], ['loaded', m.loaded_at], ['default', m.is_default ? 'yes' : 'no'],
      ['classes', m.classes.join(', ')],
      ['descriptor', `Lmax ${ds.lmax}, ${ds.method}, ${ds.steps} steps${ds.weighting ? ', ' + ds.weighting + ' weights' : ''}`],
      ['features', `${fs.family || '?'} l=${fs.l_min}..${fs.l_max}, scale ${fs.scale}${fs.log_transform ? ', log' : ''}`],
      ['training', `${ts.samples ?? '?'} samples, C=${fmt(ts.best_c)}, γ=${fmt(ts.best_gamma)}`],
      ['grid score (CV)', fmt(ts.grid_score, 3)], ['test accuracy', fmt(ts.test_accuracy, 3)],
      ['nested CV', ts.nested_cv_mean !== undefined ? `${fmt(ts.nested_cv_mean, 3)} ± ${fmt(ts.nested_cv_std, 2)}` : '—'],
      ['trained', ts.trained_at], ['dataset sha256', ts.dataset_sha256], ['notes', ts.notes],
    ];
    div.innerHTML = `<h3></h3><dl></dl>`;
    div.querySelector('h3').textContent = m.name;
    const dl = div.querySelector('dl');
    for (const [k, v] of rows) {
      if (v === undefined || v === null || v === '—') continue;
      const dt = document.createElement('dt'); dt.textContent = k;
      const dd = document.createElement('dd'); dd.textContent = v;
      dl.append(dt, dd);
    }
    div.dataset.model = m.name;
    const report = document.createElement('div');
    report.className = 'report-box';
    report.dataset.state = 'loading';
    report.textContent = 'training report: loading…';
    div.append(report);
    box.append(div);
    showReport(m.name, report);
  }
}

// The training report beside the model file, when there is one (404 report_not_found otherwise: said, not an error).
async function showReport(name, box) {
  try {
    const report = await getJson(`/v1/models/${encodeURIComponent(name)}/report`);
    box.replaceChildren(renderReport(report));
    box.dataset.state = 'shown';
  } catch (e) {
    const absent = e instanceof ApiError && e.code === 'report_not_found';
    box.dataset.state = absent ? 'absent' : 'error';
    box.dataset.code = e.code || '';
    box.className = 'report-box note' + (absent ? '' : ' error');
    box.textContent = absent ? 'No training report beside this model file.' : `training report: HTTP ${e.status} ${e.code}: ${e.message}`;
  }
}

// ------------------------------------------------------------------ options
function updateOptions() {
  const classify = $('#operation').value === 'classify';
  $('#model-label').hidden = !classify;
  // A classify request computes the model's descriptor (lmax, method must match it): only describe chooses them.
  $('#lmax-label').hidden = classify;
  $('#method-label').hidden = classify;
  $('#options-note').textContent = classify ? "Lmax and method are the model's." : '';
}

function requestPath() {
  const params = new URLSearchParams({ include: INCLUDE });
  if ($('#operation').value === 'classify') {
    if ($('#model-select').value) params.set('model', $('#model-select').value);
    return `/v1/classify?${params}`;
  }
  if ($('#lmax-input').value) params.set('lmax', $('#lmax-input').value);
  if ($('#method-select').value) params.set('method', $('#method-select').value);
  return `/v1/describe?${params}`;
}

// ------------------------------------------------------------------ uploads
const queue = [];
let running = 0;

function addFiles(files) {
  for (const file of files) {
    const item = { id: state.nextId++, file, name: file.name, status: 'queued', progress: 0, result: null, error: null,
                   path: requestPath() };
    state.items.push(item);
    queue.push(item);
  }
  renderTable();
  pump();
}

function pump() {
  while (running < CONCURRENT_UPLOADS && queue.length) {
    const item = queue.shift();
    running++;
    item.status = 'uploading';
    renderTable();
    postMesh(item.path, item.file, (fraction, phase) => { item.progress = fraction; item.status = phase; renderTable(); })
      .then((result) => { item.result = result; item.status = 'done'; })
      .catch((e) => {
        item.error = e instanceof ApiError ? e : new ApiError(0, 'client_error', String(e));
        item.status = 'error';
      })
      .finally(() => {
        running--;
        renderTable();
        if (state.selected === null || state.selected === item.id) select(item.id);
        pump();
      });
  }
}

// ------------------------------------------------------------------ batch table
function rowValues(item) {
  const r = item.result;
  const top = r?.prediction ? Math.max(...r.prediction.probabilities.map((p) => p.probability)) : null;
  return {
    file: item.name,
    status: item.status === 'error' ? `${item.error.status} ${item.error.code}` : item.status,
    label: r?.prediction?.label ?? null,
    novel: r?.prediction?.novel ?? null,  // true: none of the model's known types; null: not computed
    probability: top,
    k_p99: r?.map?.quality?.conformal_p99 ?? null,
    flips: r?.map?.quality?.flipped_faces ?? null,
    seconds: r?.timings?.total ?? null,
  };
}

function renderTable() {
  const tbody = $('#batch-table tbody');
  tbody.innerHTML = '';
  let items = [...state.items];
  const { key, dir } = state.sort;
  if (key) {
    items.sort((a, b) => {
      const va = rowValues(a)[key], vb = rowValues(b)[key];
      if (va === vb) return 0;
      if (va === null) return 1;
      if (vb === null) return -1;
      return (va < vb ? -1 : 1) * dir;
    });
  }
  for (const item of items) {
    const v = rowValues(item);
    const tr = document.createElement('tr');
    tr.dataset.id = item.id;
    tr.dataset.file = item.name;
    if (item.id === state.selected) tr.className = 'selected';
    const cells = [v.file, null, v.label ?? '', fmt(v.probability, 3), fmt(v.k_p99, 4), fmt(v.flips), fmt(v.seconds, 3)];
    cells.forEach((text, i) => {
      const td = document.createElement('td');
      if (i === 1) {
        td.dataset.status = item.status;
        if (item.status === 'uploading' || item.status === 'computing') {
          td.innerHTML = `<span class="progress"><span style="width:${Math.round(100 * item.progress)}%"></span></span> `;
          td.append(item.status);
        } else if (item.status === 'error') {
          td.className = 'error';
          td.dataset.code = item.error.code;
          td.textContent = v.status;
          td.title = item.error.message;
        } else {
          td.textContent = v.status;
        }
      } else {
        td.textContent = text;
        if (i > 2) td.className = 'num';
        if (i === 2 && v.novel === true) {  // the label stays; the badge says the model has not seen such a shape
          td.dataset.novel = 'true';
          const badge = document.createElement('span');
          badge.className = 'novel-badge';
          badge.textContent = 'novel';
          badge.title = 'Unlike every training sample of the model: probably none of its known types';
          td.append(' ', badge);
        }
      }
      tr.append(td);
    });
    tr.addEventListener('click', () => select(item.id));
    tbody.append(tr);
  }
  $('#batch-empty').hidden = state.items.length > 0;
  const anyDone = state.items.some((i) => i.status === 'done' || i.status === 'error');
  $('#download-csv').disabled = $('#download-json').disabled = !anyDone;
  document.querySelectorAll('#batch-table th').forEach((th) => {
    th.classList.toggle('sorted-asc', th.dataset.key === key && dir > 0);
    th.classList.toggle('sorted-desc', th.dataset.key === key && dir < 0);
  });
}

function download(name, type, text) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

function csvCell(v) {
  const s = v === null || v === undefined ? '' : String(v);
  return /[",\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
}

function batchCsv() {
  const head = ['file', 'status', 'error_code', 'error_message', 'label', 'top_probability', 'margin', 'novel',
                'novelty_p_value', 'flipped_faces',
                'conformal_mean', 'conformal_p99', 'conformal_max', 'area_distortion', 'roundness', 'map_method',
                'seconds', 'lmax', 'invariants'];
  const lines = [head.join(',')];
  for (const item of state.items) {
    const r = item.result, q = r?.map?.quality || {};
    const v = rowValues(item);
    lines.push([item.name, item.error ? item.error.status : item.status === 'done' ? 200 : item.status,
                item.error?.code, item.error?.message, v.label, v.probability, r?.prediction?.margin,
                r?.prediction?.novel, r?.prediction?.novelty?.p_value, q.flipped_faces,
                q.conformal_mean, q.conformal_p99, q.conformal_max, q.area_distortion, q.roundness, r?.map?.method,
                v.seconds, r?.descriptor?.lmax, (r?.descriptor?.invariants || []).join(' ')].map(csvCell).join(','));
  }
  return lines.join('\n') + '\n';
}

function batchJson() {
  // The service's results without the bulky geometry arrays (they are in each full response).
  return JSON.stringify(state.items.map((item) => {
    if (item.error) return { file: item.name, status: item.error.status, error: { code: item.error.code, message: item.error.message, details: item.error.details } };
    if (!item.result) return { file: item.name, status: item.status };
    const { geometry, ...rest } = item.result;
    return { file: item.name, status: 200, result: rest };
  }), null, 1);
}

// ------------------------------------------------------------------ one result
function ensureViewers() {
  if (viewers) return viewers;
  viewers = { input: new MeshViewer($('#input-view')), sphere: new MeshViewer($('#sphere-view')),
              recon: new MeshViewer($('#recon-view')) };
  return viewers;
}

function select(id) {
  state.selected = id;
  renderTable();
  const item = state.items.find((i) => i.id === id);
  if (!item) return;
  $('#detail-panel').hidden = false;
  $('#detail-title').textContent = item.name;
  const err = $('#detail-error');
  if (item.error) {
    err.hidden = false;
    err.innerHTML = '';
    const code = document.createElement('strong'); code.className = 'code'; code.textContent = item.error.code;
    err.append(`HTTP ${item.error.status} `, code, `: ${item.error.message}`);
    if (item.error.details && Object.keys(item.error.details).length)
      err.append(` (${JSON.stringify(item.error.details)})`);
    $('#detail-views').hidden = true;
    return;
  }
  err.hidden = true;
  if (!item.result) { $('#detail-views').hidden = true; return; }
  $('#detail-views').hidden = false;
  showResult(item);
}

function faceColours(values, kind) {
  const n = values.length, out = new Float32Array(3 * n);
  let lo, hi;
  if (kind === 'area') {  // log2 ratio, symmetric scale
    const logs = values.map((v) => (v > 0 ? Math.log2(v) : NaN));
    const [a, b] = robustRange(logs.map(Math.abs));
    hi = Math.max(b, 1e-6); lo = -hi;
    logs.forEach((v, f) => out.set(diverging(v / hi), 3 * f));
  } else {  // K >= 1
    [lo, hi] = robustRange(values.map((v) => (v === null ? Infinity : v)));
    lo = 1;
    values.forEach((v, f) => out.set(viridis(v === null ? 1 : (v - lo) / (hi - lo || 1)), 3 * f));
  }
  return { colours: { perFace: out }, lo, hi, scale: kind === 'area' ? 'diverging' : 'viridis' };
}

function vertexColours(values) {
  const [lo, hi] = robustRange(values);
  const out = new Float32Array(3 * values.length);
  values.forEach((v, i) => out.set(viridis((v - lo) / (hi - lo || 1)), 3 * i));
  return { colours: { perVertex: out }, lo, hi, scale: 'viridis' };
}

function legend(box, title, c) {
  box.innerHTML = '';
  if (!c) return;
  const bar = document.createElement('span'); bar.className = 'bar'; bar.style.background = cssGradient(c.scale);
  box.append(`${title}: ${fmt(c.lo, 3)}`, bar, `${fmt(c.hi, 3)}${c.scale === 'viridis' ? ' (p99 and above)' : ''}`);
}

function inputColouring(item, field) {
  const g = item.result.geometry, cache = item.cache;
  if (field === 'fit_error') return vertexColours(Array.from(cache.fitErrorLmax.perVertex));
  if (field === 'radius') {
    const v = g.vertices, n = v.length / 3; let cx = 0, cy = 0, cz = 0;
    for (let i = 0; i < n; ++i) { cx += v[3 * i]; cy += v[3 * i + 1]; cz += v[3 * i + 2]; }
    cx /= n; cy /= n; cz /= n;
    const r = []; for (let i = 0; i < n; ++i) r.push(Math.hypot(v[3 * i] - cx, v[3 * i + 1] - cy, v[3 * i + 2] - cz));
    return vertexColours(r);
  }
  if (field === 'conformal') return faceColours(g.conformal_distortion, 'conformal');
  if (field === 'area') return faceColours(g.area_ratio, 'area');
  return null;
}

const FIELD_TITLES = { fit_error: '|x − x_L|', radius: 'distance', conformal: 'K', area: 'log₂ area ratio' };

function drawInput(item) {
  const g = item.result.geometry;
  const field = $('#input-field').value;
  const c = inputColouring(item, field);
  viewers.input.setMesh(g.vertices, g.faces, c?.colours || null, { keepCamera: item.cache.inputShown });
  item.cache.inputShown = true;
  legend($('#input-legend'), FIELD_TITLES[field], c);
}

function drawSphere(item) {
  const g = item.result.geometry;
  const field = $('#sphere-field').value;
  const c = faceColours(field === 'area' ? g.area_ratio : g.conformal_distortion, field);
  viewers.sphere.setMesh(g.sphere, g.faces, c.colours, { keepCamera: item.cache.sphereShown });
  item.cache.sphereShown = true;
  legend($('#sphere-legend'), FIELD_TITLES[field], c);
}

function drawReconstruction(item) {
  const g = item.result.geometry, d = item.result.descriptor;
  const degree = Number($('#degree-slider').value);
  const x = evaluateSurface(d.coefficients, g.sphere, degree);
  viewers.recon.setMesh(x, g.faces, null, { keepCamera: item.cache.reconShown });
  item.cache.reconShown = true;
  const e = fitError(g.vertices, x);
  $('#degree-value').textContent = `${degree} / ${d.lmax}`;
  const stats = $('#recon-stats');
  stats.innerHTML = '';
  const span = (cls, text) => { const s = document.createElement('span'); s.className = cls; s.textContent = text; return s; };
  stats.append('mean |x − x_L| at the input vertices: ', span('recon-mean', e.mean.toPrecision(6)),
               `, max ${e.max.toPrecision(4)}`);
  if (degree === d.lmax)
    stats.append(' (service: ', span('service-mean', d.fit_error.mean.toPrecision(6)), ')');
}

const QUALITY_ROWS = [
  ['flipped_faces', 'flipped faces'], ['degenerate_faces', 'degenerate faces'], ['degree', 'degree of the map'],
  ['conformal_mean', 'K mean'], ['conformal_p99', 'K p99'], ['conformal_max', 'K max'],
  ['area_distortion', 'area distortion'], ['roundness', 'roundness'], ['mobius_centroid', 'Möbius centroid'],
  ['min_face_area', 'smallest sphere face'],
];

function showQuality(item) {
  const r = item.result, q = r.map.quality || {};
  const tbody = $('#quality-table tbody');
  tbody.innerHTML = '';
  const add = (label, value, key) => {
    const tr = document.createElement('tr');
    const a = document.createElement('td'); a.textContent = label;
    const b = document.createElement('td'); b.className = 'num'; b.textContent = value;
    if (key) b.dataset.q = key;
    tr.append(a, b); tbody.append(tr);
  };
  add('method', r.map.method, 'method');
  add('status', r.map.status, 'status');
  for (const [key, label] of QUALITY_ROWS) add(label, fmt(q[key], 6), key);
  add('map time (s)', fmt(r.map.seconds, 4), 'seconds');
  add('total time (s)', fmt(r.timings.total, 4), 'total');
  add('vertices / faces', `${r.geometry.vertex_count} / ${r.geometry.face_count}`);
  const at = $('#attempts-table tbody');
  at.innerHTML = '';
  for (const a of r.map.attempts || []) {
    const tr = document.createElement('tr');
    for (const v of [a.method + (a.filtered ? ' (filtered)' : ''), a.status, a.steps, fmt(a.seconds, 3), a.failed_check || ''])
      { const td = document.createElement('td'); td.textContent = v; tr.append(td); }
    at.append(tr);
  }
}

function showSpectrum(item) {
  const inv = item.result.descriptor.invariants || [];
  // xi(0) is the squared mean position (depends on translation): the plot starts at l = 1.
  const series = [{ name: item.name, colour: '#2563eb', values: inv.map((v, l) => [l, v]).slice(1) }];
  // The classes the shape was judged by: each class's geometric-mean spectrum exp(mean ln xi(l)) over its training
  // samples, from the model's training_summary.class_spectra (GET /v1/models), dashed.
  const p = item.result.prediction;
  const model = p ? state.models.find((m) => m.name === p.model.name) : null;
  const spectra = model?.training_summary?.class_spectra || [];
  const lmax = inv.length - 1;
  spectra.forEach((c, i) => {
    const values = c.log_xi_mean.map((v, k) => [c.l_min + k, Math.exp(v)]).filter(([l]) => l <= lmax);
    series.push({ name: `${c.label} (mean of ${c.count})`, colour: CLASS_COLOURS[i % CLASS_COLOURS.length], values,
                  dashed: true, points: false, kind: 'class-mean' });
  });
  const box = $('#spectrum');
  box.innerHTML = '';
  box.append(spectrumPlot(series, { height: Math.max(260, 40 + 14 * series.length) }));
  const note = document.createElement('p'); note.className = 'note';
  note.textContent = !p ? 'Described without a model: no class spectra to compare with.'
    : spectra.length ? 'Dashed: geometric-mean spectrum of each class of the model\'s training set.'
      : 'This model file carries no per-class spectra (trained before they were stored), so no class means are drawn.';
  box.append(note);
}

// The novelty figure (proto Novelty): whether the shape is like the model's training set at all.
function noveltyLine(p) {
  const line = document.createElement('p');
  line.id = 'novelty';
  const n = p.novelty;
  if (!n || !n.computed) {
    line.dataset.novel = 'unknown';
    line.textContent = `Novelty not computed: ${n?.reason || 'the model has no novelty calibration'}.`;
    return line;
  }
  line.dataset.novel = String(p.novel);
  // Why (issue 38): the class the shape is most like and how far, in units of that class's own spread.
  const why = n.nearest_class
    ? `; nearest class ${n.nearest_class} at ${fmt(n.distance_ratio, 3)}× its spread` +
      (n.classes?.length > 1 ? ` (${n.classes.slice(1).map((c) => `${c.label} ${fmt(c.ratio, 3)}×`).join(', ')})` : '')
    : '';
  const figures = `score ${fmt(n.score, 3)}, threshold ${fmt(n.threshold, 3)} (the training set's ${fmt(100 * n.quantile, 3)}th percentile), p = ${fmt(n.p_value, 3)}${why}`;
  if (p.novel) {
    line.className = 'novel';
    const strong = document.createElement('strong');
    strong.textContent = 'Novel: none of the known types?';
    line.append(strong, ` This shape is unlike every training sample of the model (${figures}); the label below is the nearest known type, not a finding.`);
  } else {
    line.textContent = `Within the training set's range (${figures}).`;
  }
  return line;
}

function showPrediction(item) {
  const box = $('#prediction');
  box.innerHTML = '';
  const p = item.result.prediction;
  if (!p) { box.textContent = 'Described without a model (operation "describe"): no prediction.'; return; }
  const head = document.createElement('p');
  const label = document.createElement('strong'); label.id = 'predicted-label'; label.textContent = p.label;
  head.append('label ', label, ` · margin ${fmt(p.margin, 3)} · model ${p.model.name} v${p.model.version}`);
  box.append(head, noveltyLine(p), probabilityBars(p.probabilities, p.label));
}

function showResult(item) {
  ensureViewers();
  if (!item.cache) {
    const g = item.result.geometry, d = item.result.descriptor;
    item.cache = { fitErrorLmax: fitError(g.vertices, evaluateSurface(d.coefficients, g.sphere, d.lmax)) };
  }
  // A result shown anew gets its views framed; re-colouring or moving the slider keeps the camera.
  item.cache.inputShown = item.cache.sphereShown = item.cache.reconShown = false;
  const slider = $('#degree-slider');
  slider.max = item.result.descriptor.lmax;
  slider.value = item.result.descriptor.lmax;
  drawInput(item);
  drawSphere(item);
  drawReconstruction(item);
  showQuality(item);
  showSpectrum(item);
  showPrediction(item);
}

const current = () => state.items.find((i) => i.id === state.selected && i.result);

// ------------------------------------------------------------------ wiring
function wire() {
  const zone = $('#drop-zone');
  zone.addEventListener('dragover', (e) => { e.preventDefault(); zone.classList.add('over'); });
  zone.addEventListener('dragleave', () => zone.classList.remove('over'));
  zone.addEventListener('drop', (e) => { e.preventDefault(); zone.classList.remove('over'); addFiles(e.dataTransfer.files); });
  $('#file-input').addEventListener('change', (e) => { addFiles(e.target.files); e.target.value = ''; });
  $('#operation').addEventListener('change', updateOptions);
  $('#input-field').addEventListener('change', () => current() && drawInput(current()));
  $('#sphere-field').addEventListener('change', () => current() && drawSphere(current()));
  $('#degree-slider').addEventListener('input', () => current() && drawReconstruction(current()));
  $('#wireframe').addEventListener('change', (e) => viewers && Object.values(viewers).forEach((v) => v.setWireframe(e.target.checked)));
  document.querySelectorAll('#batch-table th').forEach((th) => th.addEventListener('click', () => {
    state.sort = { key: th.dataset.key, dir: state.sort.key === th.dataset.key ? -state.sort.dir : 1 };
    renderTable();
  }));
  $('#download-csv').addEventListener('click', () => download('wish-results.csv', 'text/csv', batchCsv()));
  $('#download-json').addEventListener('click', () => download('wish-results.json', 'application/json', batchJson()));
}

wire();
loadMapMethods();
loadModels();
window.wishPage = { state };  // for inspection from the browser console (and the browser tests)
