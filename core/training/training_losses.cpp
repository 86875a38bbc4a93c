#include "core/training/training_losses.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/common/errors.hpp"

namespace wish {
namespace {

std::string reasons(const ClassLosses& c) {
  std::string out;
  for (const auto& [code, n] : c.lost_by_code) out += (out.empty() ? "" : ", ") + code + " x" + std::to_string(n);
  return out.empty() ? "-" : out;
}

std::string percent(double share) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << 100.0 * share << " %";
  return s.str();
}

}  // namespace

std::vector<ClassLosses> summarize_losses(const std::vector<std::string>& kept_labels,
                                          const std::vector<MeshLoss>& losses,
                                          const std::vector<std::string>& flagged_labels) {
  std::map<std::string, ClassLosses> by_label;
  auto row = [&](const std::string& label) -> ClassLosses& {
    ClassLosses& c = by_label[label];
    c.label = label;
    return c;
  };
  for (const auto& l : kept_labels) {
    ClassLosses& c = row(l);
    ++c.total;
    ++c.kept;
  }
  for (const auto& loss : losses) {
    ClassLosses& c = row(loss.label);
    ++c.total;
    ++c.lost_by_code[loss.code];
  }
  for (const auto& l : flagged_labels) ++row(l).flagged;
  std::vector<ClassLosses> out;
  for (auto& [label, c] : by_label) out.push_back(std::move(c));
  return out;
}

void enforce_loss_policy(const std::vector<ClassLosses>& classes, const LossPolicy& policy) {
  if (policy.allow_losses) return;
  if (!(policy.max_class_loss >= 0.0 && policy.max_class_loss <= 1.0))
    throw InvalidInputError("invalid_parameter", "the largest class loss share must be in [0, 1], got " +
                                                     std::to_string(policy.max_class_loss));
  std::string over;
  std::int64_t worst = 0;
  for (const auto& c : classes) {
    if (c.lost_share() <= policy.max_class_loss + 1e-12) continue;
    over += (over.empty() ? "" : "; ") + c.label + ": " + std::to_string(c.lost()) + " of " + std::to_string(c.total) +
            " lost (" + percent(c.lost_share()) + ": " + reasons(c) + ")";
    ++worst;
  }
  if (over.empty()) return;
  throw InvalidInputError("training_losses",
                          "training stopped: " + std::to_string(worst) + " class(es) lost more than " +
                              percent(policy.max_class_loss) + " of their meshes — " + over +
                              ". Fix the inputs, raise --max-class-loss, or pass --allow-losses to train anyway",
                          {{"classes_over_limit", worst}, {"max_class_loss", policy.max_class_loss}});
}

std::string loss_table(const std::vector<ClassLosses>& classes) {
  std::ostringstream o;
  o << std::left << std::setw(18) << "class" << std::right << std::setw(8) << "meshes" << std::setw(7) << "kept"
    << std::setw(7) << "lost" << std::setw(9) << "share" << std::setw(9) << "flagged" << "  reasons (code x count)\n";
  int total = 0, kept = 0, flagged = 0;
  for (const auto& c : classes) {
    o << std::left << std::setw(18) << c.label << std::right << std::setw(8) << c.total << std::setw(7) << c.kept
      << std::setw(7) << c.lost() << std::setw(9) << percent(c.lost_share()) << std::setw(9) << c.flagged << "  "
      << reasons(c) << "\n";
    total += c.total;
    kept += c.kept;
    flagged += c.flagged;
  }
  o << std::left << std::setw(18) << "all" << std::right << std::setw(8) << total << std::setw(7) << kept << std::setw(7)
    << total - kept << std::setw(9) << percent(total > 0 ? static_cast<double>(total - kept) / total : 0.0) << std::setw(9)
    << flagged << "\n";
  return o.str();
}

}  // namespace wish
