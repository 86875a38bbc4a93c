#pragma once
// Möbius normalisation of a sphere map by area-centre balancing (docs/design/spherical-map.md §8.3).
// A conformal map to S² is unique up to the 6-dimensional Möbius group; the 3 "boosts" are fixed by requiring
// Σ_i w_i u_i = 0 with w_i the (normalised) vertex areas of the INPUT mesh. For a ∈ B³ the ball-preserving
// Möbius map sending a to 0, restricted to S², is
//   T_a(u) = (1 − |a|²)(u − a)/|u − a|² − a     (|T_a(u)| = 1 for |u| = 1).
// Iteration: c = Σ w_i u_i; stop when |c| < tolerance; else u ← T_a(u), renormalised, with a the Newton step of
// the convex function F(a) = Σ w_i log(|u_i − a|²/(1 − |a|²)) at a = 0 (docs/design/spherical-map.md §8.3 names it the robust
// alternative): a = ½ (I − S)⁻¹ c with S = Σ w_i u_i u_iᵀ, capped at |a| ≤ max_boost and halved until |c| falls.
// The damped fixed point a = 0.5 c it replaces stalled above 1e-10 after 500 iterations on maps of elongated
// shapes (UroCell mitochondria: weight near two antipodal caps, S with an eigenvalue near 1, where 0.5 c is far
// short of the step needed). The fixed point is the Douady–Earle conformal barycentre either way (unique up to a
// rotation, which the invariants do not see). Möbius maps are orientation-preserving on S², so they introduce no
// flips (up to round-off on near-degenerate triangles).

#include <Eigen/Core>

namespace wish::spherical {

struct MobiusOptions {
  double tolerance = 1e-10;  // |Σ w_i u_i| below this stops
  int max_iterations = 100;  // Newton steps (quadratic convergence: a handful near the fixed point)
  double max_boost = 0.5;    // |a| cap of one step (T_a's expansion near a/|a| grows like 1/(1 − |a|)²)
  int max_halvings = 40;     // line search on |c| per step
};

struct MobiusResult {
  int iterations = 0;
  double centroid = 0;       // final |Σ w_i u_i| (weights normalised to sum 1)
  bool converged = false;
};

// `sphere` (V×3 unit vectors) is modified in place; `weights` ≥ 0 per vertex (need not be normalised).
MobiusResult mobius_balance(Eigen::MatrixX3d& sphere, const Eigen::VectorXd& weights, const MobiusOptions& options = {});

}  // namespace wish::spherical
