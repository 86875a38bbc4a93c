#pragma once
// Presenting a training run (docs/design/classification.md: "Report like Table 1 ... a heat map is what people want to look
// at ... also a confusion matrix, per-class precision/recall/F1, and an honest nested-CV estimate"):
// a plain-text table and an SVG heat map of the grid accuracy (ColorBrewer BuPu, as the paper). The JSON report is
// the wire library's (wire/training_report_json.hpp).

#include <string>

#include "core/training/training.hpp"

namespace wish {

std::string training_report_table(const TrainingReport& report);
std::string grid_heatmap_svg(const GridSearchResult& grid, const std::string& title);

}  // namespace wish
