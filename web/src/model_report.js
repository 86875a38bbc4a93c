// A model's training report (GET /v1/models/{name}/report, proto TrainingReport, written by `wish train` beside the
// model): the summary figures, the grid-search heat map (C × γ, mean cross-validated accuracy; the paper's Fig. 7),
// the hold-out confusion matrix (rows true, columns predicted), per-class precision / recall / F1 and, when the
// report has them, the meshes each class lost in training (refused or failed, by error code).
import { viridis } from './colormap.js';
import { fmt, heatMap } from './plots.js';

function table(head, rows, className) {
  const t = document.createElement('table');
  t.className = className;
  const thead = t.createTHead().insertRow();
  for (const h of head) { const th = document.createElement('th'); th.textContent = h; thead.append(th); }
  const body = t.createTBody();
  for (const r of rows) {
    const tr = body.insertRow();
    for (const c of r) {
      const td = tr.insertCell();
      if (c && typeof c === 'object') { td.textContent = c.text; Object.assign(td.dataset, c.data || {}); if (c.cls) td.className = c.cls; }
      else td.textContent = c;
    }
  }
  return t;
}

function heading(text) { const h = document.createElement('h4'); h.textContent = text; return h; }

export function renderReport(report) {
  const box = document.createElement('div');
  box.className = 'report';
  const test = report.test || {}, grid = report.grid || {}, ncv = report.nested_cv || {};
  const summary = document.createElement('p');
  summary.className = 'report-summary';
  summary.textContent = `${report.samples} samples, ${(report.classes || []).length} classes; grid best C = ${fmt(grid.best_C)}, ` +
    `γ = ${fmt(grid.best_gamma)} (CV ${fmt(grid.best_score, 3)}); train ${fmt(report.train_accuracy, 3)}, ` +
    `hold-out ${fmt(test.accuracy, 3)} on ${test.samples ?? '?'}, macro F1 ${fmt(test.macro_f1, 3)}` +
    (ncv.mean !== undefined ? `; nested CV ${fmt(ncv.mean, 3)} ± ${fmt(ncv.std, 2)} (${ncv.folds} folds)` : '');
  box.append(summary);

  const views = document.createElement('div');
  views.className = 'report-views';
  box.append(views);

  if (grid.C && grid.gamma && grid.mean_accuracy) {
    const v = document.createElement('div');
    v.className = 'report-grid';
    const best = [grid.C.indexOf(grid.best_C), grid.gamma.indexOf(grid.best_gamma)];
    v.append(heading('Grid search: mean CV accuracy (rows C, columns γ)'),
             heatMap(grid.C, grid.gamma, grid.mean_accuracy,
                     { rowName: 'C', colName: 'γ', best, scale: viridis, marks: grid.capped_fits }));
    if (grid.capped_fits || grid.cells_skipped) {
      const note = document.createElement('p');
      note.className = 'note grid-note';
      note.textContent = `${grid.fits ?? '?'} fits; ${grid.capped_fits_total ?? 0} stopped at libsvm's iteration cap ` +
        `(not converged; "!n" in a cell)` + (grid.cells_skipped ? `; ${grid.cells_skipped} cells skipped by early stop ("—")` : '');
      v.append(note);
    }
    views.append(v);
  }

  const labels = (report.classes || []).map((c) => c.label);
  if (test.confusion_matrix) {
    const v = document.createElement('div');
    v.className = 'report-confusion';
    const rows = test.confusion_matrix.map((row, i) => [
      { text: labels[i] ?? String(i), cls: 'label' },
      ...row.map((n, j) => ({ text: String(n), data: { row: i, col: j }, cls: i === j ? 'num diag' : n ? 'num off' : 'num' })),
    ]);
    v.append(heading('Confusion matrix, hold-out (rows true, columns predicted)'),
             table(['true \\ predicted', ...labels.map((l) => l.slice(0, 6))], rows, 'confusion'));
    views.append(v);
  }

  if (test.per_class) {
    const v = document.createElement('div');
    v.className = 'report-per-class';
    const rows = test.per_class.map((c) => [
      { text: c.label, cls: 'label' },
      ...['precision', 'recall', 'f1'].map((k) => ({ text: fmt(c[k], 3), data: { label: c.label, metric: k }, cls: 'num' })),
      { text: String(c.support), data: { label: c.label, metric: 'support' }, cls: 'num' },
    ]);
    v.append(heading('Per class, hold-out'), table(['class', 'precision', 'recall', 'F1', 'support'], rows, 'per-class'));
    if (report.losses && report.losses.length) {
      const lrows = report.losses.map((c) => [
        { text: c.label, cls: 'label' },
        ...['meshes', 'kept', 'lost'].map((k) => ({ text: String(c[k]), data: { label: c.label, metric: k }, cls: 'num' })),
        Object.entries(c.lost_by_code || {}).map(([code, n]) => `${code} ${n}`).join(', ') || '—',
      ]);
      v.append(heading('Meshes per class in training (lost: refused or failed)'),
               table(['class', 'meshes', 'kept', 'lost', 'lost by code'], lrows, 'losses'));
    }
    views.append(v);
  }
  return box;
}
