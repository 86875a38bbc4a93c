// compute_spherical_map(): the context of the mesh (map_context.hpp), the chain (map_chain.hpp) and, for an Ok
// map, the canonical map (canonical_map.hpp) or the optional area-aware correction (density_equalizing.hpp).
#include "core/spherical_map/spherical_map.hpp"

#include <chrono>

#include "core/common/cpu_budget.hpp"
#include "core/common/stage_profile.hpp"
#include "core/spherical_map/map_context.hpp"

namespace wish {
namespace {

using Clock = std::chrono::steady_clock;

// The area-aware correction of an Ok map (density_equalizing.hpp), re-verified: a corrected map that is not
// bijective (it should not happen: every step is checked) is dropped and the conformal map kept (stop Reverted).
void correct_area(const Mesh& mesh, const SphericalMapOptions& options, const Eigen::VectorXd& input_mass,
                  SphericalMapResult& result) {
  Eigen::MatrixX3d corrected = result.sphere;
  AreaCorrectionReport report = spherical::equalize_sphere_density(
      corrected, mesh.vertices, mesh.faces, options.area_correction, options.verification.degenerate_height);
  report.conformal_p99_before = result.quality.conformal_p99;
  MapQuality quality = spherical::measure_map(mesh.vertices, mesh.faces, corrected, options.verification);
  MapVerificationThresholds bijective_only = options.verification;
  bijective_only.strict_conformal_bound = false;  // the correction trades conformality for area by design
  if (spherical::failed_map_check(quality, bijective_only) != MapCheck::None) {
    report.stop = AreaCorrectionStop::Reverted;
    report.converged = false;
    report.after = report.before;
    report.conformal_p99_after = report.conformal_p99_before;
    result.area_correction = report;
    return;
  }
  report.conformal_p99_after = quality.conformal_p99;
  quality.repaired_vertices = result.quality.repaired_vertices;
  quality.roundness = result.quality.roundness;
  quality.mobius_iterations = result.quality.mobius_iterations;
  const Eigen::VectorXd w = input_mass / input_mass.sum();
  quality.mobius_centroid = Eigen::Vector3d(corrected.transpose() * w).norm();  // balance after the correction
  result.sphere = std::move(corrected);
  result.quality = quality;
  result.verdict = quality.verdict;
  result.area_correction = report;
}

// The canonical map (canonical_map.hpp) relaxed from the chain's Ok map, re-verified: every accepted step is
// bijective, so a failed re-verification is not expected; if it happens the chain's map is kept (stop Reverted).
void relax_to_canonical(const Mesh& mesh, const SphericalMapOptions& options, const Eigen::VectorXd& input_mass,
                        const Deadline& deadline, SphericalMapResult& result) {
  const profile::ScopedStage stage("map.canonical");
  Eigen::MatrixX3d relaxed = result.sphere;
  CanonicalMapReport report = spherical::relax_to_canonical_map(relaxed, mesh.vertices, mesh.faces, options.canonical,
                                                                options.verification.degenerate_height, deadline);
  deadline.check("canonical map");  // a relaxation the request's deadline stopped is a timeout, not an answer
  MapQuality quality = spherical::measure_map(mesh.vertices, mesh.faces, relaxed, options.verification);
  MapVerificationThresholds bijective_only = options.verification;
  bijective_only.strict_conformal_bound = false;  // the canonical map trades conformality for area by design
  if (spherical::failed_map_check(quality, bijective_only) != MapCheck::None) {
    report.stop = CanonicalMapStop::Reverted;
    report.converged = false;
    result.canonical = report;
    return;
  }
  quality.repaired_vertices = result.quality.repaired_vertices;
  quality.roundness = result.quality.roundness;
  quality.mobius_iterations = result.quality.mobius_iterations;
  const Eigen::VectorXd w = input_mass / input_mass.sum();
  quality.mobius_centroid = Eigen::Vector3d(relaxed.transpose() * w).norm();  // area centroid of the canonical map
  result.sphere = std::move(relaxed);
  result.quality = quality;
  result.verdict = quality.verdict;
  result.canonical = report;
}

}  // namespace

SphericalMapResult compute_spherical_map(const Mesh& mesh, const SphericalMapOptions& options, const Deadline& deadline) {
  const Clock::time_point t0 = Clock::now();
  const double cpu0 = CpuBudget::thread_cpu_seconds();
  const profile::ScopedStage stage("map");
  const spherical::MapContext context = [&] {
    const profile::ScopedStage context_stage("map.context (checks, pattern, mass)");
    return spherical::MapContext(mesh, options.solver, options.laplacian);
  }();
  spherical::ChainOutcome chain = spherical::run_chain(context, options, deadline);

  SphericalMapResult result;
  result.attempts = std::move(chain.attempts);
  result.chosen_attempt = chain.chosen_attempt;
  result.skipped_for_budget = std::move(chain.skipped_for_budget);
  result.sphere = std::move(chain.sphere);
  const MapAttempt& chosen = result.attempts[static_cast<size_t>(result.chosen_attempt)];
  result.status = chosen.status;
  result.failed_check = chosen.failed_check;
  result.quality = chosen.quality;
  result.verdict = chosen.quality.verdict;
  result.operator_stats = chosen.operator_stats;
  result.method_used = chosen.method;
  // The area correction first: from an area-balanced start the isometric relaxation has far less to do (a
  // conformal map of a long shape starves its ends exponentially; symmetric Dirichlet is ~1e8 there).
  if (options.area_correction.method != AreaCorrection::None && result.ok())
    correct_area(mesh, options, context.input_mass(), result);
  if (options.canonical.method != CanonicalMap::None && result.ok())
    relax_to_canonical(mesh, options, context.input_mass(), deadline, result);
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  result.cpu_seconds = CpuBudget::thread_cpu_seconds() - cpu0;
  return result;
}

}  // namespace wish
