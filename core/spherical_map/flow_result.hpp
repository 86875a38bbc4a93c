#pragma once
// What every map method hands to the chain (map_attempt.hpp), and what the chain hands to every method:
//  * FlowResult: the flowed surface (centred on its area-weighted centroid, total area 4π, input connectivity) or,
//    for a one-shot method, the sphere map itself (on_sphere), the step trace, why it stopped, and typed facts the
//    chain decides on (never read back from the message, which is for people);
//  * FlowControl: the limits and the starting point of one run.
// Every method has the one signature  FlowResult f(const MapContext&, const XOptions&, const FlowControl&).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/cpu_budget.hpp"
#include "core/common/deadline.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/spherical_map/map_types.hpp"

namespace wish {

// One flow step, accepted or rejected.
struct FlowStepRecord {
  int step = 0;
  double tau = 0;
  double energy = 0;                 // Willmore energy sum_i M_i H_i^2 after the step (4*pi for a round sphere)
  double roundness = 0;
  double eigen_residual = 0;         // relative residual of the smallest eigenvector
  bool accepted = true;
  double seconds = 0;
  // Added: detail of the step (Willmore flow; cMCF fills what applies).
  double rayleigh = 0;               // gamma / mean(diag E): how far rho was from integrable (0 = exactly)
  int inverse_iterations = 0;
  double eigen_shift = 0;            // epsilon actually added to the Dirac matrix
  double geometry_seconds = 0;       // normals, L, M, H, projection, Dirac assembly
  double factor_seconds = 0;         // numeric factorisation(s) of the Dirac (or cMCF) matrix
  double eigen_seconds = 0;          // inverse-iteration solves and residuals
  double poisson_seconds = 0;        // divergence, pinned-Laplacian factorisation and 3-RHS solve
  std::string note;                  // why a step was rejected, or "" when accepted
};

namespace spherical {

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
  // The linear map used the clamped, all-positive weights (Tutte/Floater): a second, clamped attempt would repeat it.
  bool clamped_weights = false;
  // The map is normalised by the method itself and is not conformal, so the Möbius group is not its gauge: the
  // chain does not balance it with the input's vertex areas (the progressive embedding: its stretch or uniform
  // spreading; balancing its map of a decimated spine with input areas squeezed faces to 1e-18 and flipped 17).
  bool keep_normalisation = false;
  geometry::IntrinsicStats operator_stats;  // the Laplacian of the input (or first) surface: repairs, flips
};

// Limits and starting point of one run of a method.
struct FlowControl {
  Deadline deadline;                        // hard, wall-clock: TimeoutError between steps
  CpuBudget budget;                         // soft, this thread's CPU: the flow stops with FlowStop::TimeBudget
  // Flowed positions to continue from (input connectivity), e.g. the surface of an earlier attempt that ran out of
  // steps ("more steps" in the chain); nullptr: start from the input. One-shot methods ignore it.
  const Eigen::MatrixX3d* start = nullptr;
};

// Centre `x` on its area-weighted centroid and scale it to total area 4π (so the flow's limit is the unit sphere).
void normalise_area_and_centre(Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces);

}  // namespace spherical
}  // namespace wish
