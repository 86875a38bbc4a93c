// Small hand-drawn SVG plots: the spectrum on a log axis, probability bars, a heat map. No plotting library: a
// few dozen lines each, no dependency to keep current.
const NS = 'http://www.w3.org/2000/svg';

function el(name, attrs = {}, text) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

export const fmt = (v, digits = 4) =>
  v === null || v === undefined ? '—' : typeof v === 'number' ? (Number.isInteger(v) ? String(v) : v.toPrecision(digits)) : String(v);

// series: [{name, values: [[l, xi], ...], colour, dashed, kind, points}]; log10 y axis. `kind` is written to the
// line's data-kind (tests find the series by it); points: false draws the line without markers.
export function spectrumPlot(series, { width = 440, height = 260 } = {}) {
  const svg = el('svg', { width, height, viewBox: `0 0 ${width} ${height}`, role: 'img', 'aria-label': 'spectrum' });
  const m = { l: 52, r: 12, t: 10, b: 34 };
  const pts = series.flatMap((s) => s.values).filter(([, y]) => y > 0 && Number.isFinite(y));
  if (!pts.length) { svg.append(el('text', { x: 10, y: 20 }, 'no positive energies')); return svg; }
  const lmin = Math.min(...pts.map((p) => p[0])), lmax = Math.max(...pts.map((p) => p[0]));
  let ymin = Math.floor(Math.log10(Math.min(...pts.map((p) => p[1]))));
  let ymax = Math.ceil(Math.log10(Math.max(...pts.map((p) => p[1]))));
  if (ymax === ymin) ymax = ymin + 1;
  const X = (l) => m.l + ((l - lmin) / Math.max(1, lmax - lmin)) * (width - m.l - m.r);
  const Y = (y) => height - m.b - ((Math.log10(y) - ymin) / (ymax - ymin)) * (height - m.t - m.b);
  const step = Math.max(1, Math.ceil((ymax - ymin) / 6));
  for (let e = ymin; e <= ymax; e += step) {
    svg.append(el('line', { x1: m.l, x2: width - m.r, y1: Y(10 ** e), y2: Y(10 ** e), stroke: '#eaecf0' }));
    svg.append(el('text', { x: m.l - 6, y: Y(10 ** e) + 4, 'text-anchor': 'end' }, `1e${e}`));
  }
  const lstep = Math.max(1, Math.ceil((lmax - lmin) / 12));
  for (let l = lmin; l <= lmax; l += lstep)
    svg.append(el('text', { x: X(l), y: height - m.b + 14, 'text-anchor': 'middle' }, String(l)));
  svg.append(el('text', { x: (m.l + width - m.r) / 2, y: height - 4, 'text-anchor': 'middle' }, 'degree l'));
  svg.append(el('text', { x: 12, y: m.t + 8 }, 'ξ(l)'));
  series.forEach((s, i) => {
    const v = s.values.filter(([, y]) => y > 0 && Number.isFinite(y));
    svg.append(el('polyline', { points: v.map(([l, y]) => `${X(l)},${Y(y)}`).join(' '), fill: 'none',
                                stroke: s.colour, 'stroke-width': s.dashed ? 1.5 : 2, 'stroke-dasharray': s.dashed ? '4 3' : 'none',
                                'data-kind': s.kind || 'shape', 'data-name': s.name,
                                'data-values': JSON.stringify(v.map(([, y]) => y)) }));
    if (s.points !== false)
      for (const [l, y] of v) svg.append(el('circle', { cx: X(l), cy: Y(y), r: 3, fill: s.colour, 'data-l': l, 'data-xi': y }));
    svg.append(el('text', { x: width - m.r - 4, y: m.t + 12 + 14 * i, 'text-anchor': 'end', fill: s.colour }, s.name));
  });
  return svg;
}

// probabilities: [{label, probability}], winner label highlighted.
export function probabilityBars(probabilities, winner) {
  const box = document.createElement('div');
  box.className = 'bars';
  for (const { label, probability } of probabilities) {
    const row = document.createElement('div');
    row.className = 'row' + (label === winner ? ' winner' : '');
    row.dataset.label = label;
    row.innerHTML = `<span class="name"></span><span><div class="fill"></div></span><span class="num"></span>`;
    row.querySelector('.name').textContent = label;
    row.querySelector('.fill').style.width = `${(100 * probability).toFixed(1)}%`;
    row.querySelector('.num').textContent = probability.toFixed(3);
    box.append(row);
  }
  return box;
}
