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

// A grid-search heat map: values[i][j] at row rows[i], column cols[j] (for the training report: rows C, columns γ,
// values the mean cross-validated accuracy), coloured by `scale` (t in [0, 1] -> [r, g, b] in [0, 1]) over the
// values' [min, max] and printed in each cell. `best`
// = [i, j] is outlined. Each cell carries data-row, data-col and data-value (the JSON number) for tests.
// marks (optional): a count per cell drawn in its corner as "!n" when > 0 (the grid search's fits that stopped at
// libsvm's iteration cap). A null value is a cell that was not evaluated (early stop): grey, "—".
export function heatMap(rows, cols, values, { rowName = 'C', colName = 'γ', best = null, cell = 30, digits = 2,
                                                scale = () => [0.6, 0.6, 0.6], marks = null } = {}) {
  const m = { l: 58, t: 12, r: 12, b: 44 };
  const width = m.l + cols.length * cell + m.r, height = m.t + rows.length * cell + m.b;
  const svg = el('svg', { width, height, viewBox: `0 0 ${width} ${height}`, role: 'img', 'aria-label': 'grid heat map',
                          class: 'heatmap' });
  const flat = values.flat().filter(Number.isFinite);
  const lo = Math.min(...flat), hi = Math.max(...flat);
  const tick = (v) => {
    const e = Math.log10(v);
    return Math.abs(e - Math.round(e)) < 1e-9 ? `1e${Math.round(e)}` : fmt(v, 2);
  };
  rows.forEach((r, i) => {
    svg.append(el('text', { x: m.l - 4, y: m.t + i * cell + cell / 2 + 4, 'text-anchor': 'end' }, tick(r)));
    cols.forEach((c, j) => {
      const v = values[i]?.[j];
      const t = hi > lo ? (v - lo) / (hi - lo) : 1;
      const fill = `rgb(${scale(t).map((c) => Math.round(255 * c)).join(',')})`;
      const x = m.l + j * cell, y = m.t + i * cell;
      const isBest = best && best[0] === i && best[1] === j;
      const g = el('g', { class: 'cell' + (isBest ? ' best' : ''), 'data-row': i, 'data-col': j, 'data-value': v });
      g.append(el('rect', { x, y, width: cell, height: cell, fill: Number.isFinite(v) ? fill : '#eee',
                            stroke: isBest ? '#dc2626' : '#fff', 'stroke-width': isBest ? 2.5 : 0.5 }));
      // Dark cells get white digits (viridis is dark at the low end).
      g.append(el('text', { x: x + cell / 2, y: y + cell / 2 + 4, 'text-anchor': 'middle', class: 'value',
                            style: `fill:${t < 0.55 ? '#fff' : '#111'};font-size:${cell < 32 ? 9 : 11}px` },
                  Number.isFinite(v) ? v.toFixed(digits) : '—'));
      const mark = marks?.[i]?.[j];
      if (mark > 0) {
        g.dataset.capped = mark;
        g.append(el('text', { x: x + cell - 2, y: y + 8, 'text-anchor': 'end', class: 'capped',
                              style: 'fill:#dc2626;font-size:7px;font-weight:bold' }, `!${mark}`));
      }
      svg.append(g);
    });
  });
  cols.forEach((c, j) => svg.append(el('text', { x: m.l + j * cell + cell / 2, y: m.t + rows.length * cell + 14,
                                                 'text-anchor': 'middle', style: 'font-size:9px' }, tick(c))));
  svg.append(el('text', { x: m.l + (cols.length * cell) / 2, y: height - 8, 'text-anchor': 'middle' }, colName));
  svg.append(el('text', { x: 12, y: m.t + (rows.length * cell) / 2, 'text-anchor': 'middle',
                          transform: `rotate(-90 12 ${m.t + (rows.length * cell) / 2})` }, rowName));
  return svg;
}
