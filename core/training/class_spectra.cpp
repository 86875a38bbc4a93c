#include "core/training/class_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wish {

std::vector<ClassSpectrum> class_spectra(const std::vector<TrainingSample>& samples, const std::vector<std::string>& classes) {
  constexpr double kFloor = 1e-300;  // ln(0) would be -inf, which JSON cannot hold
  std::vector<ClassSpectrum> out;
  for (const auto& label : classes) {
    ClassSpectrum c;
    c.label = label;
    Eigen::Index length = std::numeric_limits<Eigen::Index>::max();
    for (const auto& s : samples)
      if (s.label == label) {
        ++c.count;
        length = std::min(length, std::max<Eigen::Index>(0, s.features.invariants.size() - 1));
      }
    if (c.count == 0) {
      out.push_back(std::move(c));
      continue;
    }
    // Two passes (mean, then squared deviations): exact enough for a few thousand samples and no cancellation.
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(length), m2 = Eigen::VectorXd::Zero(length);
    auto logs = [&](const TrainingSample& s) {
      return s.features.invariants.segment(1, length).cwiseMax(kFloor).array().log().matrix().eval();
    };
    for (const auto& s : samples)
      if (s.label == label) mean += logs(s);
    mean /= static_cast<double>(c.count);
    for (const auto& s : samples)
      if (s.label == label) m2 += (logs(s) - mean).cwiseAbs2();
    // Population standard deviation (divide by n): a description of the training set, not an estimate.
    const Eigen::VectorXd sd = (m2 / static_cast<double>(c.count)).cwiseSqrt();
    c.log_xi_mean.assign(mean.data(), mean.data() + mean.size());
    c.log_xi_std.assign(sd.data(), sd.data() + sd.size());
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace wish
