#pragma once
// What a flow (Willmore or cMCF) hands to the sphere-map stage: the flowed surface (centred on its area-weighted
// centroid, total area 4π, input connectivity), the step trace, and whether the flow converged.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/spherical_map/spherical_map.hpp"

namespace wish::spherical {

struct FlowResult {
  Eigen::MatrixX3d vertices;          // the surface to project: the last one, or (cMCF) the roundest of the flow
  // The flow's last surface where `vertices` is an earlier, rounder one (cMCF stopped at its cap or a stall); empty
  // otherwise. A continued flow starts from here: restarting from `vertices` would replay the steps after it.
  Eigen::MatrixX3d last;
  std::vector<FlowStepRecord> steps;  // accepted and rejected, in order
  MapStatus status = MapStatus::Ok;   // Ok (a stopping criterion was met), NotConverged or SolverFailed
  MapCheck failed_check = MapCheck::None;
  FlowStop stop = FlowStop::None;
  std::string message;
  double initial_energy = 0, energy = 0;  // Willmore energy Σ M_i H_i² before / after
  double initial_roundness = 0, roundness = 0;
  bool on_sphere = false;             // vertices are already the sphere map (linear method): no radial projection
  bool hit_step_cap = false;          // ran out of steps while still improving (so "more steps" may help)
  geometry::IntrinsicStats operator_stats;  // the Laplacian of the input (or first) surface: repairs, flips
};

// Centre `x` on its area-weighted centroid and scale it to total area 4π (so the flow's limit is the unit sphere).
void normalise_area_and_centre(Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces);

}  // namespace wish::spherical
