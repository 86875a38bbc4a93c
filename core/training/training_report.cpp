#include "core/training/training_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>


#include "core/classify/feature_pipeline.hpp"
#include "core/training/decision_spread.hpp"

namespace wish {
namespace {


std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string exponent_label(double v) {
  const double e = std::log10(v);
  if (std::abs(e - std::round(e)) < 1e-9) return "1e" + std::to_string(static_cast<int>(std::round(e)));
  return fmt("%.3g", v);
}

// ColorBrewer BuPu, 9 classes, interpolated linearly in sRGB.
std::string bupu(double t) {
  static const int stops[9][3] = {{247, 252, 253}, {224, 236, 244}, {191, 211, 230}, {158, 188, 218}, {140, 150, 198},
                                  {140, 107, 177}, {136, 65, 157},  {129, 15, 124},  {77, 0, 75}};
  t = std::clamp(t, 0.0, 1.0) * 8;
  const int i = std::min(static_cast<int>(t), 7);
  const double f = t - i;
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", static_cast<int>(std::lround(stops[i][0] + f * (stops[i + 1][0] - stops[i][0]))),
                static_cast<int>(std::lround(stops[i][1] + f * (stops[i + 1][1] - stops[i][1]))),
                static_cast<int>(std::lround(stops[i][2] + f * (stops[i + 1][2] - stops[i][2]))));
  return buf;
}

}  // namespace

std::string training_report_table(const TrainingReport& r) {
  std::ostringstream o;
  o << "samples " << r.samples << ", classes " << r.classes.size() << ", features " << r.feature_names.size() << " ("
    << to_string(r.spec.family) << ")\n";
  o << "best C = " << exponent_label(r.grid.C()) << ", gamma = " << exponent_label(r.grid.gamma())
    << "  (grid validation accuracy " << fmt("%.3f", r.grid.best_score) << ")\n";
  if (!r.search_reason.empty()) o << "search: " << r.search_reason << "\n";
  if (!r.grid.rungs.empty()) {
    o << "halving rungs (rows: cells):";
    for (const auto& g : r.grid.rungs) o << " " << g.rows << ": " << g.candidates;
    o << "; best scored on " << r.grid.search_rows << " rows\n";
  }
  o << "grid: " << r.grid.fits << " fits";
  if (r.grid.early_stop)
    o << ", " << r.grid.cells_skipped << " of " << r.grid.Cs.size() * r.grid.gammas.size()
      << " cells skipped by early stop (a gamma row, once risen, stops after " << r.grid.early_stop_patience
      << " consecutive C not above its best - " << fmt("%.3g", r.grid.early_stop_drop) << ")";
  o << "; " << r.grid.total_capped_fits() << " fits stopped at libsvm's iteration cap (not converged)";
  if (r.grid.total_capped_fits() > 0) {
    o << " in cells";
    int shown = 0;
    for (Eigen::Index ci = 0; ci < r.grid.capped_fits.rows(); ++ci)
      for (Eigen::Index gi = 0; gi < r.grid.capped_fits.cols(); ++gi)
        if (r.grid.capped_fits(ci, gi) > 0 && shown++ < 6)
          o << " (C " << exponent_label(r.grid.Cs[ci]) << ", gamma " << exponent_label(r.grid.gammas[gi]) << ": "
            << r.grid.capped_fits(ci, gi) << ")";
    if (shown > 6) o << " ...";
  }
  o << "\n";
  if (r.grid.cells_offset_decided > 0)
    o << "grid: " << r.grid.cells_offset_decided << " cells decided by the SVM's offset (most fits' decision values "
      << "spread less than the margin width " << fmt("%.3g", kMarginSpread) << " over their training rows), "
      << (r.grid.best_offset_decided ? "and so is the best cell: every scored cell was" : "never chosen") << "\n";
  if (r.grid.best_offset_decided)
    o << "WARNING: the chosen cell is decided by the offset; the model may put every sample into the larger class "
         "(check the training accuracy and the confusion matrix)\n";
  if (!r.nested.scores.empty())
    o << "nested CV inner searches: " << r.nested.fits << " fits, " << r.nested.capped_fits
      << " stopped at the iteration cap, " << r.nested.cells_skipped << " cells skipped by early stop\n";
  if (r.novelty_threshold > 0) {
    int flagged = 0;
    for (bool b : r.test_novel) flagged += b;
    o << "novelty: a sample is novel above every class's threshold (the " << fmt("%.3g", r.novelty_quantile)
      << " quantile of the class's "
      << (r.novelty_folds > 0 ? std::to_string(r.novelty_folds) + "-fold cross-validated" : std::string("leave-one-out"))
      << " k-NN distances):";
    for (std::size_t c = 0; c < r.novelty_class_thresholds.size() && c < r.classes.size(); ++c)
      o << " " << r.classes[c] << " " << fmt("%.4g", r.novelty_class_thresholds[c]);
    if (!r.test_novel.empty()) o << "; " << flagged << " of " << r.test_novel.size() << " held-out samples flagged novel";
    o << "\n";
  }
  if (!r.train_classes_never_predicted.empty()) {
    o << "WARNING: the model predicts none of its training samples as";
    for (const auto& c : r.train_classes_never_predicted) o << " " << c;
    o << " (" << r.train_classes_never_predicted.size() << " of " << r.classes.size()
      << " classes): it merged them into others; check the grid's chosen cell and the confusion matrix\n";
  }
  if (r.final_fit_cap_warnings > 0)
    o << "the final model's fit: " << r.final_fit_cap_warnings << " solvers stopped at libsvm's iteration cap\n";
  o << "train accuracy " << fmt("%.3f", r.train_accuracy) << ", test accuracy " << fmt("%.3f", r.test.accuracy) << " on "
    << r.test_indices.size() << " held-out samples";
  if (!r.nested.scores.empty()) {
    o << ", nested CV " << fmt("%.3f", r.nested.mean) << " +- " << fmt("%.3f", r.nested.std) << " (" << r.nested.scores.size()
      << " outer folds";
    if (r.nested.interval95)
      o << "; 95 % interval " << fmt("%.3f", r.nested.interval95->low) << "-" << fmt("%.3f", r.nested.interval95->high);
    o << ")";
  }
  o << "\n\n";
  if (!r.losses.empty()) o << "meshes per class (lost: refused or failed, by error code; flagged: off-recipe maps kept)\n"
                           << loss_table(r.losses) << "\n";
  std::size_t w = 10;
  for (const auto& c : r.classes) w = std::max(w, c.size() + 1);
  char buf[256];
  std::snprintf(buf, sizeof buf, "%-*s %9s %9s %9s %8s\n", static_cast<int>(w), "class", "precision", "recall", "f1", "support");
  o << buf;
  for (const auto& m : r.test.per_class) {
    std::snprintf(buf, sizeof buf, "%-*s %9.3f %9.3f %9.3f %8d\n", static_cast<int>(w), m.label.c_str(), m.precision, m.recall,
                  m.f1, m.support);
    o << buf;
  }
  o << "\nconfusion matrix (rows: true, columns: predicted)\n";
  std::snprintf(buf, sizeof buf, "%-*s", static_cast<int>(w), "");
  o << buf;
  for (const auto& c : r.classes) o << " " << c.substr(0, 6) << std::string(c.size() < 6 ? 6 - c.size() : 0, ' ');
  o << "\n";
  for (Eigen::Index i = 0; i < r.test.confusion.rows(); ++i) {
    std::snprintf(buf, sizeof buf, "%-*s", static_cast<int>(w), r.classes[static_cast<std::size_t>(i)].c_str());
    o << buf;
    for (Eigen::Index j = 0; j < r.test.confusion.cols(); ++j) {
      std::snprintf(buf, sizeof buf, " %6d", r.test.confusion(i, j));
      o << buf;
    }
    o << "\n";
  }
  return o.str();
}

std::string grid_heatmap_svg(const GridSearchResult& g, const std::string& title) {
  const int nc = static_cast<int>(g.Cs.size()), ng = static_cast<int>(g.gammas.size());
  const int cell = 40, left = 80, top = 50, right = 90, bottom = 60;
  const int width = left + ng * cell + right, height = top + nc * cell + bottom;
  // Skipped cells (early stop) are NaN: the colour range is over evaluated cells only.
  double lo = 1, hi = 0;
  for (Eigen::Index i = 0; i < g.mean_score.size(); ++i)
    if (!std::isnan(g.mean_score.data()[i])) {
      lo = std::min(lo, g.mean_score.data()[i]);
      hi = std::max(hi, g.mean_score.data()[i]);
    }
  if (lo > hi) lo = 0, hi = 1;
  auto escape = [](std::string s) {
    std::string out;
    for (char ch : s) {
      if (ch == '<') out += "&lt;";
      else if (ch == '>') out += "&gt;";
      else if (ch == '&') out += "&amp;";
      else out += ch;
    }
    return out;
  };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
    << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << left << "\" y=\"20\" font-size=\"14\">" << escape(title) << "</text>\n";
  const bool halving = g.cell_rung.size() > 0 && !g.rungs.empty();
  o << "<text x=\"" << left << "\" y=\"38\">mean validation accuracy; best C = " << exponent_label(g.C()) << ", gamma = "
    << exponent_label(g.gamma()) << " (" << fmt("%.3f", g.best_score) << "); !n: fits stopped at the iteration cap"
    << (g.cells_skipped ? "; grey: skipped (early stop)" : "")
    << (g.cells_offset_decided ? "; o: decided by the offset (not chosen)" : "")
    << (halving ? "; rN: successive halving's rung N (" + std::to_string(g.rungs.front().rows) + " to " +
                      std::to_string(g.rungs.back().rows) + " rows), scores of different rungs differ in rows"
                : std::string())
    << "</text>\n";
  for (int ci = 0; ci < nc; ++ci) {
    for (int gi = 0; gi < ng; ++gi) {
      const double v = g.mean_score(ci, gi);
      const int x = left + gi * cell, y = top + ci * cell;
      const int capped = g.capped_fits.size() ? g.capped_fits(ci, gi) : 0;
      const bool offset = g.cell_offset_decided(ci, gi);
      const std::string where = "C=" + exponent_label(g.Cs[ci]) + " gamma=" + exponent_label(g.gammas[gi]);
      if (std::isnan(v)) {
        o << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"" << cell << "\" height=\"" << cell
          << "\" fill=\"#e5e5e5\"><title>" << where << ": skipped (early stop)</title></rect>\n";
        o << "<text x=\"" << x + cell / 2 << "\" y=\"" << y + cell / 2 + 4
          << "\" text-anchor=\"middle\" font-size=\"9\" fill=\"#777\">&#8212;</text>\n";
        continue;
      }
      const double t = hi > lo ? (v - lo) / (hi - lo) : 1.0;
      o << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"" << cell << "\" height=\"" << cell << "\" fill=\"" << bupu(t)
        << "\"><title>" << where << ": " << fmt("%.3f", v)
        << (capped ? "; " + std::to_string(capped) + " fits stopped at the iteration cap" : std::string())
        << (offset ? "; decided by the offset in " + std::to_string(g.narrow_fits(ci, gi)) + " of " +
                         std::to_string(g.splits_per_cell) + " fits"
                   : std::string())
        << "</title></rect>\n";
      o << "<text x=\"" << x + cell / 2 << "\" y=\"" << y + cell / 2 + 4 << "\" text-anchor=\"middle\" font-size=\"9\" fill=\""
        << (t > 0.55 ? "white" : "black") << "\">" << fmt("%.2f", v) << "</text>\n";
      if (halving)  // the rung (so the rows) this cell's score is from
        o << "<text x=\"" << x + 2 << "\" y=\"" << y + 10 << "\" font-size=\"8\" fill=\"" << (t > 0.55 ? "white" : "#555")
          << "\">r" << g.cell_rung(ci, gi) << "</text>\n";
      if (offset)  // a bottom-left mark: the cell's fits are decided by the SVM's offset (decision_spread.hpp)
        o << "<text x=\"" << x + 2 << "\" y=\"" << y + cell - 3 << "\" font-size=\"8\" fill=\""
          << (t > 0.55 ? "white" : "#555") << "\">o</text>\n";
      if (capped)  // a corner mark with the count: fits of this cell that did not converge
        o << "<text x=\"" << x + cell - 2 << "\" y=\"" << y + 10 << "\" text-anchor=\"end\" font-size=\"8\" fill=\"#d7301f\">!"
          << capped << "</text>\n";
    }
    o << "<text x=\"" << left - 6 << "\" y=\"" << top + ci * cell + cell / 2 + 4 << "\" text-anchor=\"end\">"
      << exponent_label(g.Cs[ci]) << "</text>\n";
  }
  for (int gi = 0; gi < ng; ++gi)
    o << "<text x=\"" << left + gi * cell + cell / 2 << "\" y=\"" << top + nc * cell + 16
      << "\" text-anchor=\"middle\" font-size=\"9\">" << exponent_label(g.gammas[gi]) << "</text>\n";
  o << "<text x=\"" << left + ng * cell / 2 << "\" y=\"" << top + nc * cell + 40 << "\" text-anchor=\"middle\">gamma</text>\n";
  o << "<text x=\"20\" y=\"" << top + nc * cell / 2 << "\" transform=\"rotate(-90 20 " << top + nc * cell / 2
    << ")\" text-anchor=\"middle\">C</text>\n";
  o << "<rect x=\"" << left + g.best_gamma * cell + 1 << "\" y=\"" << top + g.best_c * cell + 1 << "\" width=\"" << cell - 2
    << "\" height=\"" << cell - 2 << "\" fill=\"none\" stroke=\"#e6550d\" stroke-width=\"3\"/>\n";
  // Colour bar.
  const int bx = left + ng * cell + 20;
  for (int i = 0; i < 100; ++i)
    o << "<rect x=\"" << bx << "\" y=\"" << top + (99 - i) * nc * cell / 100 << "\" width=\"16\" height=\""
      << nc * cell / 100 + 1 << "\" fill=\"" << bupu(i / 99.0) << "\"/>\n";
  o << "<text x=\"" << bx + 20 << "\" y=\"" << top + 8 << "\">" << fmt("%.2f", hi) << "</text>\n";
  o << "<text x=\"" << bx + 20 << "\" y=\"" << top + nc * cell << "\">" << fmt("%.2f", lo) << "</text>\n";
  o << "</svg>\n";
  return o.str();
}

}  // namespace wish
