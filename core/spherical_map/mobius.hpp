#pragma once
// Möbius normalisation of a sphere map by area-centre balancing (spherical-map.md §8.3).
// A conformal map to S² is unique up to the 6-dimensional Möbius group; the 3 "boosts" are fixed by requiring
// Σ_i w_i u_i = 0 with w_i the (normalised) vertex areas of the INPUT mesh. For a ∈ B³ the ball-preserving
// Möbius map sending a to 0, restricted to S², is
//   T_a(u) = (1 − |a|²)(u − a)/|u − a|² − a     (|T_a(u)| = 1 for |u| = 1).
// Iteration: c = Σ w_i u_i; stop when |c| < tolerance; else u ← T_{αc}(u), renormalised. The damping α starts at
// 0.5 and is halved whenever |c| grows. The fixed point is the Douady–Earle conformal barycentre. Möbius maps are
// orientation-preserving on S², so they introduce no flips (up to round-off on near-degenerate triangles).

#include <Eigen/Core>

namespace wish::spherical {

struct MobiusOptions {
  double tolerance = 1e-10;  // |Σ w_i u_i| below this stops
  int max_iterations = 500;
  double damping = 0.5;      // α
};

struct MobiusResult {
  int iterations = 0;
  double centroid = 0;       // final |Σ w_i u_i| (weights normalised to sum 1)
  bool converged = false;
};

// `sphere` (V×3 unit vectors) is modified in place; `weights` ≥ 0 per vertex (need not be normalised).
MobiusResult mobius_balance(Eigen::MatrixX3d& sphere, const Eigen::VectorXd& weights, const MobiusOptions& options = {});

}  // namespace wish::spherical
