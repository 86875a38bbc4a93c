#pragma once
// Area-aware correction of a verified conformal sphere map (issue 11/12 "area-aware variant";
// docs/design/real-meshes.md "Area-aware variants"). Beyond the paper: the paper's descriptor uses the
// conformal map, which keeps angles and gives up area — a thin neck or protrusion is squeezed to 1e-6 of the sphere
// and is invisible to an SH fit at any practical Lmax. This step moves the sphere points, starting from the
// (Möbius-normalised, verified) conformal map, until every part of the surface covers a share of the sphere close
// to its share of the input area.
//
// Method: a density-equalising flow (Choi & Rycroft 2018, "Density-equalizing maps for simply connected open
// surfaces", SIAM J. Imaging Sci. 11(2); spherical version: Lyu, Choi, Lui et al., "Spherical density-equalizing
// map for genus-0 closed surfaces", arXiv:2401.11124, code garyptchoi/spherical-density-equalizing-map). There a
// density ρ = input area / sphere area diffuses, ρ_t = Δρ, and every point moves with the velocity v = −∇ρ/ρ
// (mass is conserved: ρ_t + ∇·(ρv) = 0); at t → ∞ ρ is uniform, i.e. sphere areas are proportional to input
// areas. We use a Lagrangian mass-transport flow of the same kind (the Moser / Dacorogna–Moser construction of
// an authalic map: Moser 1965; Dacorogna & Moser 1990), with the density of DEM:
//  * per step, the density is measured afresh from the moving mesh (mass is carried by the vertices: m_i and a_i
//    are the input and sphere area SHARES of vertex i, μ_i = m_i / a_i; no interpolation, no drift);
//  * the potential ψ of the excess mass solves L ψ = 4π (m − a), L the robust intrinsic cotan Laplacian of the
//    INPUT mesh (intrinsic_laplacian.hpp; cotan weights are conformally invariant, so it is the sphere's Laplacian
//    at the conformal start), factorised once — a global, smooth velocity potential where DEM diffuses ρ;
//  * every vertex moves along v = −∇ψ / μ (face gradients on the chord triangles, area-averaged, projected on
//    the tangent plane), by step · v, capped at max_step × its shortest incident sphere edge, then is projected
//    back onto the unit sphere.
// MEASURED (tests/spherical_map/density_equalizing_test.cpp): the step control stops this flow early (plateau
// after ~10 steps with many halvings), so it reduces the area distortion only modestly (cMCF map of a 4:1:1
// ellipsoid: p99 |log r| 6.30 -> 5.50; dumbbell with neck 0.15: 19.72 -> 19.67). It is an option, not a default.
// Step control keeps the map bijective: a step that makes any sphere face flipped or numerically degenerate
// (is_bad_sphere_face, the test of map verification) or that raises the area energy E = Σ_f m_f (log r_f)² by more than max_energy_rise
// (r_f = sphere share / input share) is rejected and retried at half length; after max_halvings halvings in a row
// the flow stops (StepRejected) with the last accepted (bijective) map. The caller re-verifies the result.
// The flow is rotation-equivariant (every quantity is built from dot and cross products of the sphere points), so
// the SH invariants of the corrected map stay rotation-invariant; on a map that is already equiareal (a round
// sphere onto itself) ρ is constant, ∇φ̃ = 0 and nothing moves.
// Conventions: faces CCW seen from outside; sphere rows are unit vectors; areas are chord-triangle areas, taken as
// shares of their sum (so the chord/sphere area difference cancels); input faces of (near) zero area (a real mesh's
// twin-vertex faces) carry no mass and are left out of the distortion figures, as in measure_map.

#include <string>

#include <Eigen/Core>

namespace wish {

// The correction applied after the conformal map: none (the paper's map) or the density-equalising flow.
enum class AreaCorrection { None, DensityEqualizing };
const char* to_string(AreaCorrection correction);                   // "none" | "density_equalizing"
AreaCorrection area_correction_from_name(const std::string& name);  // also "dem"; throws InvalidInputError

struct AreaCorrectionOptions {
  AreaCorrection method = AreaCorrection::None;
  int max_iterations = 60;      // accepted steps at most
  double tolerance = 0.1;       // converged when p99 of |log r_f| is below (r within ≈ ±10 %)
  double plateau = 1e-3;        // ... or stop (plateau) when E has not fallen below (1 − plateau) × its best ...
  int plateau_steps = 5;        // ... for this many accepted steps (the best map seen is returned)
  double max_energy_rise = 0.05;  // a step raising E by more than this fraction is rejected (halved)
  double step = 0.5;            // step length (time of the Moser flow per step, sphere units), before the cap
  double max_step = 0.5;        // cap: a vertex moves at most this fraction of its shortest incident edge per step
  int max_halvings = 8;         // rejected halvings in a row before the flow stops (StepRejected)
  // CPU seconds of the calling thread per 10,000 vertices (at least this many seconds); 0 = no budget. The map's
  // flow budget (SphericalMapOptions::flow_budget_seconds, 2 s) is separate: this one bounds the correction.
  double budget_seconds = 1.0;
  bool operator==(const AreaCorrectionOptions&) const = default;
};

// Why the correction stopped: "not_run" (method none, or the conformal map was not Ok), "converged" (tolerance),
// "plateau", "iteration_cap", "step_rejected" (no bijective, energy-decreasing step down to max_halvings halvings),
// "time_budget", "reverted" (the corrected map failed re-verification; the conformal map is kept).
enum class AreaCorrectionStop { NotRun, Converged, Plateau, IterationCap, StepRejected, TimeBudget, Reverted };
const char* to_string(AreaCorrectionStop stop);

// Area distortion of a sphere map: r_f = (sphere area share) / (input area share) over faces of non-zero input area.
struct AreaDistortionFigures {
  double log_ratio_p99 = 0, log_ratio_max = 0;  // of |log r_f|
  double energy = 0;                            // Σ_f m_f (log r_f)²
  double area_distortion = 0;                   // exp(mean |log r_f|), as MapQuality::area_distortion
};

struct AreaCorrectionReport {
  AreaCorrection method = AreaCorrection::None;
  AreaCorrectionStop stop = AreaCorrectionStop::NotRun;
  bool converged = false;             // stop is Converged or Plateau
  int iterations = 0;                 // accepted steps
  int rejected_steps = 0;             // halvings (a step that flipped a face or raised E)
  AreaDistortionFigures before, after;
  double conformal_p99_before = 0, conformal_p99_after = 0;  // K p99 (filled by compute_spherical_map)
  double seconds = 0;                 // CPU seconds of the calling thread
};

namespace spherical {

AreaDistortionFigures area_distortion_figures(const Eigen::MatrixX3d& input_vertices, const Eigen::MatrixX3i& faces,
                                              const Eigen::MatrixX3d& sphere);

// Moves `sphere` (V×3 unit vectors of a bijective map of input_vertices/faces) in place; ignores options.method.
// `min_height`: the verification's degenerate_height (a step must keep every face above it and unflipped).
AreaCorrectionReport equalize_sphere_density(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                                             const Eigen::MatrixX3i& faces, const AreaCorrectionOptions& options,
                                             double min_height);

}  // namespace spherical
}  // namespace wish
