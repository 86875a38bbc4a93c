// compute_spherical_map(): flow → radial projection → Möbius balancing → verification, with the fallback chain
// (spherical-map.md §7): more steps → filtered flow → cMCF (for method Willmore), every attempt recorded.
#include "core/spherical_map/spherical_map.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "core/common/errors.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/roundness.hpp"
#include "core/geometry/vertex_pattern.hpp"
#include "core/spherical_map/cmcf.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/mobius.hpp"
#include "core/spherical_map/willmore_flow.hpp"

namespace wish {

const char* to_string(MapMethod method) {
  switch (method) {
    case MapMethod::Willmore: return "willmore";
    case MapMethod::Cmcf: return "cmcf";
  }
  return "?";
}

MapMethod map_method_from_name(const std::string& name) {
  if (name == "willmore") return MapMethod::Willmore;
  if (name == "cmcf") return MapMethod::Cmcf;
  throw InvalidInputError("invalid_parameter", "unknown map method '" + name + "' (expected willmore or cmcf)",
                          {{"method", name}});
}

const char* to_string(MapStatus status) {
  switch (status) {
    case MapStatus::Ok: return "ok";
    case MapStatus::NotConverged: return "not_converged";
    case MapStatus::VerificationFailed: return "verification_failed";
    case MapStatus::SolverFailed: return "solver_failed";
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;

void check_preconditions(const Mesh& mesh) {
  const Eigen::Index nv = mesh.vertex_count(), nf = mesh.face_count();
  if (nv < 4 || nf < 4)
    throw InvalidInputError("too_small", "a closed mesh needs at least 4 vertices and 4 faces (got " +
                                             std::to_string(nv) + " and " + std::to_string(nf) + ")");
  if (!mesh.vertices.allFinite()) throw InvalidInputError("non_finite_vertex", "mesh has NaN/Inf coordinates");
  if (mesh.faces.minCoeff() < 0 || mesh.faces.maxCoeff() >= nv)
    throw InvalidInputError("index_out_of_range", "face index outside [0, #V)");
  const geometry::VertexPattern pattern = geometry::build_vertex_pattern(nv, mesh.faces);
  const long chi = static_cast<long>(nv) - pattern.edge_count + static_cast<long>(nf);
  if (chi != 2 || 3 * nf != 2 * pattern.edge_count)
    throw InvalidInputError("genus_nonzero",
                            "mesh is not a closed genus-0 surface (V - E + F = " + std::to_string(chi) +
                                ", 3F = " + std::to_string(3 * nf) + ", 2E = " + std::to_string(2 * pattern.edge_count) +
                                "); run prepare_for_mapping first",
                            {{"euler_characteristic", std::int64_t{chi}}});
  const Eigen::VectorXd areas = geometry::face_areas(mesh.vertices, mesh.faces);
  const Eigen::Index degenerate = (areas.array() <= 0).count();
  if (degenerate > 0)
    throw InvalidInputError("degenerate_faces", std::to_string(degenerate) + " faces have zero area",
                            {{"count", std::int64_t{degenerate}}});
  const double volume = geometry::signed_volume(mesh.vertices, mesh.faces);
  if (!(volume > 0))
    throw InvalidInputError("inconsistent_orientation",
                            "signed volume " + std::to_string(volume) + " is not positive: faces must be outward (CCW)",
                            {{"signed_volume", volume}});
}

struct AttemptPlan {
  MapMethod method;
  bool filtered;
  int max_steps;
};

MapAttempt run_attempt(const Mesh& mesh, const AttemptPlan& plan, const SphericalMapOptions& options,
                       const Eigen::VectorXd& input_mass, const Deadline& deadline, Eigen::MatrixX3d& sphere) {
  const Clock::time_point t0 = Clock::now();
  MapAttempt attempt;
  attempt.method = plan.method;
  attempt.filtered = plan.filtered;
  attempt.max_steps = plan.max_steps;
  spherical::FlowResult flow;
  if (plan.method == MapMethod::Willmore) {
    WillmoreOptions w = options.willmore;
    w.filtered = plan.filtered;
    w.max_steps = plan.max_steps;
    flow = spherical::willmore_flow(mesh, w, options.solver, deadline);
  } else {
    CmcfOptions c = options.cmcf;
    c.max_steps = plan.max_steps;
    flow = spherical::cmcf_flow(mesh, c, options.solver, deadline);
  }
  attempt.steps = std::move(flow.steps);
  attempt.hit_step_cap = flow.status == MapStatus::NotConverged && flow.failed_check == "roundness";
  // Radial projection about the area-weighted centroid, then Möbius balancing with input vertex areas.
  const Eigen::VectorXd mass = geometry::lumped_mass(flow.vertices, mesh.faces);
  const Eigen::Vector3d c = geometry::area_weighted_centroid(flow.vertices, mass);
  sphere = flow.vertices.rowwise() - c.transpose();
  sphere.rowwise().normalize();
  spherical::MobiusResult mobius;
  if (sphere.allFinite()) mobius = spherical::mobius_balance(sphere, input_mass);
  attempt.quality = spherical::measure_map(mesh.vertices, mesh.faces, sphere, options.verification);
  attempt.quality.roundness = flow.roundness;
  attempt.quality.mobius_centroid = mobius.centroid;
  attempt.quality.mobius_iterations = mobius.iterations;
  const std::string failed = spherical::failed_map_check(attempt.quality, options.verification);
  if (flow.status == MapStatus::SolverFailed) {
    attempt.status = MapStatus::SolverFailed;
    attempt.failed_check = flow.failed_check;
    attempt.message = flow.message;
  } else if (!failed.empty()) {
    attempt.status = MapStatus::VerificationFailed;
    attempt.failed_check = failed;
    attempt.message = "map failed verification: " + failed + " (flips " + std::to_string(attempt.quality.flipped_faces) +
                      ", degenerate " + std::to_string(attempt.quality.degenerate_faces) + ", degree " +
                      std::to_string(attempt.quality.degree) + ", K p99 " + std::to_string(attempt.quality.conformal_p99) +
                      ", roundness " + std::to_string(flow.roundness) + ")";
    if (!flow.message.empty()) attempt.message += "; flow: " + flow.message;
  } else if (flow.status == MapStatus::NotConverged) {
    attempt.status = MapStatus::NotConverged;
    attempt.failed_check = flow.failed_check;
    attempt.message = flow.message;
  } else if (!mobius.converged) {
    attempt.status = MapStatus::NotConverged;
    attempt.failed_check = "mobius";
    attempt.message = "Möbius balancing stopped at centroid " + std::to_string(mobius.centroid);
  }
  attempt.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return attempt;
}

}  // namespace

SphericalMapResult compute_spherical_map(const Mesh& mesh, const SphericalMapOptions& options, const Deadline& deadline) {
  const Clock::time_point t0 = Clock::now();
  check_preconditions(mesh);
  const Eigen::VectorXd input_mass = geometry::lumped_mass(mesh.vertices, mesh.faces);

  std::vector<AttemptPlan> plans;
  if (options.method == MapMethod::Willmore) {
    const int n = options.willmore.max_steps;
    plans.push_back({MapMethod::Willmore, options.willmore.filtered, n});
    if (options.fallback) {
      plans.push_back({MapMethod::Willmore, options.willmore.filtered, 2 * n});  // more steps
      if (!options.willmore.filtered) plans.push_back({MapMethod::Willmore, true, 2 * n});
      plans.push_back({MapMethod::Cmcf, false, options.cmcf.max_steps});
      plans.push_back({MapMethod::Cmcf, false, 3 * options.cmcf.max_steps});
    }
  } else {
    plans.push_back({MapMethod::Cmcf, false, options.cmcf.max_steps});
    if (options.fallback) {
      plans.push_back({MapMethod::Cmcf, false, 3 * options.cmcf.max_steps});
      plans.push_back({MapMethod::Willmore, false, options.willmore.max_steps});
      plans.push_back({MapMethod::Willmore, true, 2 * options.willmore.max_steps});
    }
  }

  SphericalMapResult result;
  for (size_t k = 0; k < plans.size(); ++k) {
    // "More steps" only helps a flow that ran out of steps; skip it otherwise (it would repeat the same run).
    if (k > 0 && plans[k].method == plans[k - 1].method && plans[k].filtered == plans[k - 1].filtered &&
        !result.attempts.back().hit_step_cap)
      continue;
    deadline.check("spherical map attempt");
    Eigen::MatrixX3d sphere;
    MapAttempt attempt = run_attempt(mesh, plans[k], options, input_mass, deadline, sphere);
    result.sphere = std::move(sphere);
    result.status = attempt.status;
    result.failed_check = attempt.failed_check;
    result.quality = attempt.quality;
    result.method_used = attempt.method;
    result.attempts.push_back(std::move(attempt));
    if (result.status == MapStatus::Ok) break;
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return result;
}

}  // namespace wish
