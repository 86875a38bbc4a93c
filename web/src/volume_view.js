// The label volume view (issue 39 item 3): an uploaded label volume classified with its class map
// (POST /v1/classify?output=labels), shown as three orthogonal slices through the volume with every object coloured
// by its predicted class (the class map's legend: class_map.values), the legend, and the table of objects; a click on
// an object in a slice selects its row (and a click on a row moves the slices to the object).
// Slices are drawn for NIfTI uploads (the class map comes back as NIfTI; decoded by nifti.js); for TIFF and OME-Zarr
// uploads the legend and the table are shown and the class map can be saved. Self-contained: the panel and its
// styles are made here, beside the page's other panels.
import { ApiError, postMesh } from './api.js';
import { fmt } from './plots.js';
import { readNifti } from './nifti.js';

const $ = (sel, root = document) => root.querySelector(sel);
const BACKGROUND = [24, 24, 27];
const DROPPED = [70, 70, 76];  // voxels of an object the filters dropped (a speck): not an object, shown dim
const PANEL = `
  <h2>Label volume <span class="actions"><button id="vol-save" disabled>Save class map</button></span></h2>
  <div class="options">
    <label class="link">Choose a label volume (NIfTI .nii / .nii.gz, TIFF, OME-Zarr .zip)
      <input type="file" id="vol-input" hidden></label>
    <span id="vol-status" class="note"></span>
  </div>
  <div id="vol-error" class="error" hidden></div>
  <div id="vol-body" hidden>
    <div id="vol-slices">
      <figure><canvas id="vol-xy"></canvas><figcaption>xy, z <input type="range" id="vol-z"> <span id="vol-z-v"></span></figcaption></figure>
      <figure><canvas id="vol-xz"></canvas><figcaption>xz, y <input type="range" id="vol-y"> <span id="vol-y-v"></span></figcaption></figure>
      <figure><canvas id="vol-yz"></canvas><figcaption>yz, x <input type="range" id="vol-x"> <span id="vol-x-v"></span></figcaption></figure>
    </div>
    <ul id="vol-legend"></ul>
    <div id="vol-selected" class="note"></div>
    <table id="vol-table"><thead><tr><th>label id</th><th>class</th><th>probability</th><th>margin</th><th>novel</th>
      <th>status</th><th>voxels</th><th>genus / repair</th></tr></thead><tbody></tbody></table>
  </div>`;
const STYLE = `
  #volume-panel #vol-slices { display: flex; gap: 12px; flex-wrap: wrap; }
  #volume-panel figure { margin: 0; }
  #volume-panel canvas { image-rendering: pixelated; background: #18181b; cursor: crosshair; }
  #volume-panel figcaption { font-size: 12px; }
  #volume-panel #vol-legend { list-style: none; padding: 0; display: flex; gap: 14px; flex-wrap: wrap; font-size: 13px; }
  #volume-panel .swatch { display: inline-block; width: 12px; height: 12px; border: 1px solid #555; margin-right: 4px; vertical-align: -1px; }
  #volume-panel #vol-table tr.selected { outline: 2px solid #2563eb; background: #dbeafe; }
  #volume-panel #vol-table tbody tr { cursor: pointer; }`;

// What the view holds (window.wishVolume, for the browser tests and the console).
const view = { result: null, volume: null, classMap: null, legend: new Map(), slice: [0, 0, 0], selected: null,
               objects: new Map() };

function rgbOf(value) { return view.legend.get(value)?.rgb ?? BACKGROUND; }

// ---------------------------------------------------------------- drawing
// The three slices through view.slice: each pixel the colour of its class map value (dropped objects dim), with a
// thin crosshair at the other two slices.
function draw() {
  if (!view.classMap) return;
  const [nx, ny, nz] = view.classMap.dims;
  const [x0, y0, z0] = view.slice;
  const index = (x, y, z) => x + nx * (y + ny * z);
  const sp = view.result.volume.spacing;
  const paint = (canvas, w, h, voxel, cross, su, sv) => {
    canvas.width = w; canvas.height = h;
    const k = 256 / Math.max(w * su, h * sv);  // physical proportions, the longer side 256 px
    canvas.style.width = `${Math.round(w * su * k)}px`;
    canvas.style.height = `${Math.round(h * sv * k)}px`;
    const ctx = canvas.getContext('2d');
    const img = ctx.createImageData(w, h);
    for (let v = 0; v < h; ++v)
      for (let u = 0; u < w; ++u) {
        const i = voxel(u, v);
        const value = view.classMap.values[i];
        const rgb = value ? rgbOf(value) : view.volume && view.volume.values[i] ? DROPPED : BACKGROUND;
        const p = 4 * (u + w * (h - 1 - v));  // v up
        img.data.set([...rgb, 255], p);
      }
    ctx.putImageData(img, 0, 0);
    ctx.fillStyle = 'rgba(255,255,255,0.35)';
    ctx.fillRect(cross[0], 0, 1, h);
    ctx.fillRect(0, h - 1 - cross[1], w, 1);
  };
  paint($('#vol-xy'), nx, ny, (u, v) => index(u, v, z0), [x0, y0], sp[0], sp[1]);
  paint($('#vol-xz'), nx, nz, (u, v) => index(u, y0, v), [x0, z0], sp[0], sp[2]);
  paint($('#vol-yz'), ny, nz, (u, v) => index(x0, u, v), [y0, z0], sp[1], sp[2]);
  for (const [axis, k] of [['x', 0], ['y', 1], ['z', 2]]) {
    $(`#vol-${axis}`).value = view.slice[k];
    $(`#vol-${axis}-v`).textContent = view.slice[k];
  }
}

// ---------------------------------------------------------------- which object a voxel belongs to
// Labels: the uploaded value is the label id. A mask (components): the object whose voxels hold this one — its
// 6-connected component of foreground, matched to the object whose box contains it with the nearest centroid
// (a fragment merged into an object is in that object's box).
function objectAt(i) {
  if (!view.volume || !view.classMap.values[i]) return null;
  const summary = view.result.volume;
  if (summary.object_mode === 'labels') return view.objects.get(view.volume.values[i]) ?? null;
  const [nx, ny] = view.volume.dims;
  const x = i % nx, y = Math.floor(i / nx) % ny, z = Math.floor(i / (nx * ny));
  let best = null, bestDistance = Infinity;
  for (const o of view.objects.values()) {
    const b0 = o.object.bbox_min, b1 = o.object.bbox_max;
    if (x < b0[0] || y < b0[1] || z < b0[2] || x > b1[0] || y > b1[1] || z > b1[2]) continue;
    const c = o.object.centroid.map((v, k) => v / view.result.volume.spacing[k]);
    const d = (c[0] - x) ** 2 + (c[1] - y) ** 2 + (c[2] - z) ** 2;
    if (d < bestDistance) { best = o; bestDistance = d; }
  }
  return best;
}

function select(entry, move) {
  view.selected = entry ? entry.label_id : null;
  for (const tr of document.querySelectorAll('#vol-table tbody tr'))
    tr.classList.toggle('selected', Number(tr.dataset.id) === view.selected);
  const row = entry && $(`#vol-table tbody tr[data-id="${entry.label_id}"]`);
  if (row) row.scrollIntoView({ block: 'nearest' });
  $('#vol-selected').textContent = entry ? describe(entry) : '';
  if (entry && move) {
    view.slice = entry.object.centroid.map((v, k) =>
      Math.min(view.classMap.dims[k] - 1, Math.max(0, Math.round(v / view.result.volume.spacing[k]))));
    draw();
  }
}

function describe(entry) {
  const p = entry.result?.prediction;
  const what = p ? `${p.label} (p ${fmt(probabilityOf(p))}, margin ${fmt(p.margin)}${p.novel ? ', NOVEL' : ''})`
    : `refused: ${entry.error?.code} ${entry.error?.message ?? ''}`;
  return `object ${entry.label_id}: ${what}; ${entry.object.voxel_count} voxels`;
}

function probabilityOf(p) { return p.probabilities.find((q) => q.label === p.label)?.probability ?? null; }

function onCanvasClick(canvas, toVoxel) {
  canvas.addEventListener('click', (e) => {
    const r = canvas.getBoundingClientRect();
    const u = Math.floor((e.clientX - r.left) / r.width * canvas.width);
    const v = canvas.height - 1 - Math.floor((e.clientY - r.top) / r.height * canvas.height);
    const [x, y, z] = toVoxel(u, v);
    const [nx, ny] = view.classMap.dims;
    view.slice = [x, y, z];
    select(objectAt(x + nx * (y + ny * z)), false);
    draw();
  });
}

// ---------------------------------------------------------------- table and legend
function render() {
  const r = view.result;
  view.legend = new Map(r.class_map.values.map((v) => [v.value, v]));
  view.objects = new Map(r.objects.map((o) => [o.label_id, o]));
  const counts = new Map();
  for (const o of r.objects) counts.set(o.class_value, (counts.get(o.class_value) ?? 0) + 1);
  $('#vol-legend').innerHTML = '';
  for (const v of r.class_map.values) {
    const li = document.createElement('li');
    li.dataset.value = v.value;
    li.innerHTML = `<span class="swatch" style="background: rgb(${v.rgb.join(',')})"></span>${v.value} ${v.name} ` +
      `<span class="note">(${counts.get(v.value) ?? 0})</span>`;
    $('#vol-legend').append(li);
  }
  const tbody = $('#vol-table tbody');
  tbody.innerHTML = '';
  for (const o of r.objects) {
    const p = o.result?.prediction;
    const t = o.object.topology;
    const tr = document.createElement('tr');
    tr.dataset.id = o.label_id;
    const cells = [o.label_id, `<span class="swatch" style="background: rgb(${rgbOf(o.class_value).join(',')})"></span>` +
                   (p ? p.label : '—'), p ? fmt(probabilityOf(p)) : '', p ? fmt(p.margin) : '', p ? (p.novel ? 'yes' : 'no') : '',
                   o.error ? `${o.status} ${o.error.code}` : o.status, o.object.voxel_count,
                   t ? `${t.genus_before}${t.repair ? ` / ${t.repaired ? t.repair.method : 'over bound'}` : ''}` : ''];
    tr.innerHTML = cells.map((c) => `<td>${c}</td>`).join('');
    tr.addEventListener('click', () => select(o, true));
    tbody.append(tr);
  }
  const s = r.volume;
  const dropped = s.dropped_objects?.length ?? 0;
  $('#vol-status').textContent = `${s.dims.join('×')} ${s.datatype}, ${s.objects_kept} objects` +
    (dropped ? `, ${dropped} dropped (specks listed in the table's JSON)` : '') + `; class map ${r.class_map.filename}`;
}

// ---------------------------------------------------------------- upload
function base64Bytes(text) {
  const raw = atob(text);
  const out = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; ++i) out[i] = raw.charCodeAt(i);
  return out;
}

async function upload(file) {
  $('#vol-error').hidden = true;
  $('#vol-body').hidden = true;
  $('#vol-save').disabled = true;
  Object.assign(view, { result: null, volume: null, classMap: null, selected: null });
  const params = new URLSearchParams({ output: 'labels' });
  const model = $('#model-select')?.value;
  if (model) params.set('model', model);
  try {
    $('#vol-status').textContent = 'uploading…';
    view.result = await postMesh(`/v1/classify?${params}`, file,
                                 (f, phase) => { $('#vol-status').textContent = `${phase} ${Math.round(100 * f)} %`; },
                                 (status, body) => Array.isArray(body.objects) && body.class_map !== undefined);
    render();
    $('#vol-save').disabled = false;
    $('#vol-body').hidden = false;
    if (view.result.class_map.format === 'nifti') {
      view.classMap = await readNifti(base64Bytes(view.result.class_map.data));
      view.volume = await readNifti(new Uint8Array(await file.arrayBuffer()));
      view.slice = view.classMap.dims.map((n) => Math.floor(n / 2));
      for (const [axis, k] of [['x', 0], ['y', 1], ['z', 2]]) {
        $(`#vol-${axis}`).min = 0;
        $(`#vol-${axis}`).max = view.classMap.dims[k] - 1;
      }
      $('#vol-slices').hidden = false;
      draw();
    } else {
      $('#vol-slices').hidden = true;  // the slices are drawn from NIfTI class maps; the others can be saved
    }
  } catch (e) {
    const err = e instanceof ApiError ? e : new ApiError(0, 'client_error', String(e));
    $('#vol-error').textContent = `${err.status || ''} ${err.code}: ${err.message}`;
    $('#vol-error').hidden = false;
    $('#vol-status').textContent = '';
  }
}

function save() {
  const cm = view.result?.class_map;
  if (!cm) return;
  const url = URL.createObjectURL(new Blob([base64Bytes(cm.data)], { type: cm.media_type }));
  const a = Object.assign(document.createElement('a'), { href: url, download: cm.filename });
  a.click();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

// ---------------------------------------------------------------- panel
function mount() {
  const style = document.createElement('style');
  style.textContent = STYLE;
  document.head.append(style);
  const panel = document.createElement('section');
  panel.id = 'volume-panel';
  panel.className = 'panel';
  panel.innerHTML = PANEL;
  (document.querySelector('main') ?? document.body).append(panel);  // last: the mesh panels keep their place
  $('#vol-input').addEventListener('change', (e) => { if (e.target.files[0]) upload(e.target.files[0]); e.target.value = ''; });
  $('#vol-save').addEventListener('click', save);
  for (const [axis, k] of [['x', 0], ['y', 1], ['z', 2]])
    $(`#vol-${axis}`).addEventListener('input', (e) => { view.slice[k] = Number(e.target.value); draw(); });
  onCanvasClick($('#vol-xy'), (u, v) => [u, v, view.slice[2]]);
  onCanvasClick($('#vol-xz'), (u, v) => [u, view.slice[1], v]);
  onCanvasClick($('#vol-yz'), (u, v) => [view.slice[0], u, v]);
}

mount();
window.wishVolume = view;
