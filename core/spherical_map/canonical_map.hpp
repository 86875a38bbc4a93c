#pragma once
// The canonical sphere map (issue 37, "one descriptor for every map"): whatever produced the first bijective map of
// a mesh — a conformal flow, the linear map, the progressive embedding — the descriptor is computed on the map of
// ONE stated definition, so that two meshes of the same shape get the same ξ whichever path their map took:
//
//   the bijective map u: M → S² that minimises a distortion energy  E(u) = Σ_f w_f ψ(F_f),
//   w_f = A_f / Σ A (the input surface's area share of face f), F_f the 2×2 deformation gradient of face f from the
//   input triangle, scaled so that the surface's total area is 4π, to its chord triangle on the unit sphere;
//   ψ the symmetric Dirichlet energy σ₁² + σ₂² + σ₁⁻² + σ₂⁻² by default (distortion_energy.hpp).
//
// Why this definition (docs/accuracy.md, issue 37): a conformal map is unique only up to Möbius transformations and
// squeezes a long or thin part exponentially (a spine's head or a coil's far end to 1e-10 of the sphere), so the
// flows that compute it stall on such meshes and the fallback maps that replace them are other parameterisations
// altogether (the off-recipe losses of training). An isometric-as-possible map balances angle and area distortion:
// every part of the surface keeps a share of the sphere close to its share of the area (what the SH fit needs), the
// minimiser is unique up to a rotation of the sphere (to which ξ is invariant: no Möbius gauge remains), and it is
// reached from ANY bijective start because ψ is a barrier against degenerate and flipped triangles. This is the
// sphere case of Schmidt, Rustamov, Hormann 2019 ("Distortion-minimizing injective maps between surfaces") and
// the symmetric Dirichlet parameterisations of Smith & Schaefer 2015 and Liu et al. 2018.
//
// Method: projected Newton on the sphere. Each vertex moves in its tangent plane (2 unknowns), then back onto the
// sphere (u ← (u + T δ)/‖u + T δ‖). Per face, ψ's Hessian in vec(F) is projected to positive semidefinite (4×4
// eigen-decomposition) and mapped to the tangent unknowns of the face's three vertices; the assembled 2V × 2V system
// (plus a small shift: global rotations are a null space) is factored by CHOLMOD (one symbolic analysis per mesh).
// A backtracking line search accepts a step only when every sphere face stays unflipped and above the map
// verification's degenerate height (is_bad_sphere_face) and the energy decreases (Armijo), so every accepted map is
// bijective. The reference triangles come from the input's edge lengths mollified as in intrinsic_laplacian.hpp
// (one ε added to every length; a real mesh's zero-area faces become thin, valid triangles).
//
// Conventions: faces CCW seen from outside; sphere rows are unit vectors; the energy is reported per unit area
// (Σ w_f = 1), so its least possible value is ψ's minimum (4 for symmetric Dirichlet) and "excess" = E − minimum.

#include <string>

#include <Eigen/Core>

#include "core/common/deadline.hpp"
#include "core/spherical_map/distortion_energy.hpp"

namespace wish {

// Which map the descriptor is computed on: the chain's own map (the paper's conformal map; recipes before version
// 4) or the canonical map above, whatever attempt of the chain produced the start.
enum class CanonicalMap { None, Isometric };

const char* to_string(CanonicalMap method);                    // "none" | "isometric"
CanonicalMap canonical_map_from_name(const std::string& name);  // throws InvalidInputError

struct CanonicalMapOptions {
  CanonicalMap method = CanonicalMap::None;
  spherical::DistortionEnergy energy;  // symmetric Dirichlet by default
  // Mollification margin δ of the reference edge lengths, relative to the mean edge length (intrinsic_laplacian.hpp
  // uses 1e-5 for its operator; the reference metric here tolerates a coarser margin: needle faces carry little
  // area, and a needle reference forces a needle image, which only slows the solver).
  double mollify_delta = 1e-3;
  // Newton steps at most: the CPU budget is the limit that binds (measured, bench/canonical_map_bench: progressive
  // starts of generated octopi and dumbbells converge in 325–424 steps, 3.6–5.8 s at 3,000 vertices).
  int max_iterations = 1000;
  // Converged when the Newton decrement (−gᵀδ, the predicted decrease) is below tolerance × (E − minimum) or below
  // absolute_tolerance (E per unit area; the excess of an already round map is ~0).
  double tolerance = 1e-6;
  double absolute_tolerance = 1e-10;
  int max_halvings = 40;       // line-search halvings of one step before it stops (LineSearchFailed)
  // CPU seconds of the calling thread per 10,000 vertices (at least this many seconds); 0 = no budget.
  double budget_seconds = 6.0;
  // Levenberg–Marquardt shift scaled per unknown by the Hessian's diagonal (Marquardt 1963) instead of by its mean.
  bool scaled_damping = true;
  // After a full Newton step, try 2×, 4×, ... the step while the energy falls (a barrier's Newton step is short).
  bool extrapolate = true;
  bool operator==(const CanonicalMapOptions&) const = default;
};

// Why the relaxation stopped. NotRun: method None, or the chain's map was not Ok. Reverted: the result failed the
// map's re-verification (not expected: every accepted step is bijective); the chain's map is kept.
enum class CanonicalMapStop { NotRun, Converged, IterationCap, TimeBudget, LineSearchFailed, SolverFailed, Reverted };

const char* to_string(CanonicalMapStop stop);  // "not_run", "converged", "iteration_cap", ...

struct CanonicalMapReport {
  CanonicalMap method = CanonicalMap::None;
  CanonicalMapStop stop = CanonicalMapStop::NotRun;
  bool converged = false;       // stop == Converged
  int iterations = 0;           // accepted Newton steps
  int halvings = 0;             // line-search halvings over all steps
  int extrapolations = 0;       // accepted doublings past a full step (options.extrapolate)
  double energy_start = 0;      // E of the start map (per unit area; +inf if a face of the start was degenerate)
  double energy = 0;            // E of the returned map
  double last_decrement = 0;    // the Newton decrement of the last step (what the convergence test read)
  double shift = 0;             // the largest diagonal shift the factorisations needed
  double seconds = 0;           // CPU seconds of the calling thread
};

namespace spherical {

// Relaxes `sphere` (V×3 unit vectors of a BIJECTIVE map of input_vertices/faces) in place to the canonical map;
// ignores options.method. `min_height`: the map verification's degenerate height (kept by every accepted step).
// Never throws for numerical trouble: the report says how it ended, and `sphere` is always the last accepted
// (bijective) map. Throws InvalidInputError when the sizes disagree.
// `deadline`: the request's hard, wall-clock limit; when it has passed the relaxation stops (TimeBudget) before the
// next step and the caller's deadline.check() reports the timeout.
CanonicalMapReport relax_to_canonical_map(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                                          const Eigen::MatrixX3i& faces, const CanonicalMapOptions& options,
                                          double min_height, const Deadline& deadline = {});

// The energy E(u) of a sphere map as defined above (per unit area); +infinity when a face is flipped or below
// min_height. For tests and reports.
double canonical_map_energy(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                            const Eigen::MatrixX3i& faces, const CanonicalMapOptions& options, double min_height);

}  // namespace spherical
}  // namespace wish
