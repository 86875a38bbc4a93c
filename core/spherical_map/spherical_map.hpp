#pragma once
// Conformal map of a closed genus-0 mesh onto the unit sphere (paper §4; docs/design/spherical-map.md).
// Entry point: compute_spherical_map(). Methods: discrete Willmore flow in curvature space with spin
// transformations (Crane, Pinkall, Schröder 2013), conformalized mean curvature flow (Kazhdan et al. 2012) and the
// linear puncture/harmonic/stereographic method (FLASH, Choi et al. 2015; bijective by construction).
// Every map is projected to the sphere, Möbius-normalised (area-centre balancing with input vertex areas as
// weights) and verified; a map that fails verification is never reported as Ok. With `fallback`, a failed attempt
// is followed by the chain of docs/design/spherical-map.md §7 (more steps → filtered flow → cMCF → linear method), stopping at
// the first Ok attempt that is final (a repaired, still distorted Ok map is provisional: the chain goes on within
// its budget); every attempt is recorded, and the returned map is the least distorted Ok attempt or, when none is
// Ok, the least-bad one (see SphericalMapResult). Local repair: untangle_in_charts (chart_untangle.hpp), then the
// Tutte relaxation (untangle.hpp), both bounded by the chain's CPU budget (SphericalMapOptions::chain_budget_seconds).
//
// Preconditions: the mesh passed prepare_for_mapping() (closed, manifold, one component, genus 0, outward).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/deadline.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/spherical_map/density_equalizing.hpp"
#include "core/mesh/mesh.hpp"

namespace wish {

enum class MapMethod { Willmore, Cmcf, Linear };
enum class LinearSolverKind { Cholmod, EigenSimplicial };

// Why a map or a flow failed (empty = None). Machine-readable names via to_string: "non_finite", "flipped_faces",
// "degenerate_faces", "degree", "conformal_distortion", "roundness", "energy", "eigen_residual", "solver",
// "mobius", "time_budget".
enum class MapCheck {
  None, NonFinite, FlippedFaces, DegenerateFaces, Degree, ConformalDistortion, Roundness, Energy, EigenResidual,
  Solver, Mobius, TimeBudget
};
const char* to_string(MapCheck check);

// Why a flow stopped: "converged" (roundness tolerance), "energy_plateau", "roundness_plateau", "energy_stall" (no
// step down to min_tau lowers E), "step_cap", "rejected_steps" (τ fell below min_tau for another reason),
// "solver_failed", "non_finite", "time_budget", or "none" (a one-shot method: the linear map).
enum class FlowStop {
  None, Converged, EnergyPlateau, RoundnessPlateau, EnergyStall, StepCap, RejectedSteps, SolverFailed, NonFinite,
  TimeBudget
};
const char* to_string(FlowStop stop);

// Distortion verdict of a bijective map: "good" (K p99 within max_conformal_p99), "distorted" (bijective, above it:
// still a usable descriptor, reported rather than refused unless strict_conformal_bound), "failed" (not bijective).
enum class MapVerdict { Good, Distorted, Failed };
const char* to_string(MapVerdict verdict);

const char* to_string(MapMethod method);
MapMethod map_method_from_name(const std::string& name);  // "willmore" | "cmcf" | "linear"; throws InvalidInputError
const char* to_string(LinearSolverKind solver);
LinearSolverKind linear_solver_from_name(const std::string& name);  // "cholmod" | "eigen_simplicial"; throws InvalidInputError

struct WillmoreOptions {
  double tau = 0.95;                 // dimensionless step: rho = -tau * P(H) (docs/design/spherical-map.md §3)
  int max_steps = 20;                // step cap (the paper uses 10 on nuclei)
  double roundness_tolerance = 2e-3; // stop when std(r)/mean(r) falls below
  // ... or when the relative energy decrease per step falls below (a stalled flow: the map is then accepted if it
  // verifies — bijective, bounded distortion — whatever the roundness; coarse meshes plateau at R ~ 1e-2).
  // A step whose energy rises for every tau down to min_tau is the same kind of stall.
  double energy_tolerance = 1e-4;
  // Added: ... or when the roundness falls by less than this fraction in a step (R plateau). A healthy flow halves R
  // per step (docs/design/spherical-map.md §9); on coarse or staircase meshes R levels off at ~1e-2 while the energy keeps
  // creeping down by ~0.5 %/step and K slowly drifts (cf. the peanut in §9: "stop early rather than iterating
  // long"). Same treatment as an energy plateau: a stop, judged by verification. Only while the energy also falls
  // by less than roundness_stall_energy per step: an R that stalls or rises while E still drops fast (homer, spool:
  // −20…−80 %/step) is the flow reshaping the surface, not a plateau.
  double roundness_stall = 0.05;
  double roundness_stall_energy = 0.05;
  double min_tau = 0.05;             // step rejection halves tau down to this, then gives up
  bool filtered = false;             // low-pass filtered flow for noisy segmentation meshes
  double filter_strength = 2.0;      // sigma = filter_strength * (mean edge length)^2
  int max_inverse_iterations = 5;    // inverse power iteration for the smallest eigenvector
  // Added: an eigen-solve whose relative residual stays above this after max_inverse_iterations rejects the step.
  double max_eigen_residual = 1e-4;
  double energy_increase_tolerance = 1e-3;  // reject a step raising E_W by more than this fraction
  // Added: solve the Dirac eigenproblem in its complex Hermitian 2V×2V form (same λ, ~2× fewer Cholesky flops)
  // instead of the real symmetric 4V×4V form (docs/design/spherical-map.md §4, §9).
  bool complex_dirac = true;
  bool operator==(const WillmoreOptions&) const = default;
};

struct CmcfOptions {
  double delta = 1.0;                // time step at total area 4*pi
  int max_steps = 30;
  double roundness_tolerance = 5e-3;
  // Added: stop (stalled; accepted if the map verifies) when, after min_steps_before_stall steps, R decreases by
  // less than this fraction per step.
  double roundness_stall = 1e-3;
  int min_steps_before_stall = 10;
  // Added: ... for this many steps in a row (1: the first step that does not lower R stops the flow). The flow
  // returns its roundest surface. Chosen on the 91 UroCell mitochondria (bench/map_collection_bench --method cmcf,
  // the chain of a cMCF model): patience 1 stalled cMCF at R ≈ 0.14 on the way down, and 76 ended on a cMCF map;
  // 10: 80; 15: 86; 20: 87, but the longer flows left the fallbacks too little of the CPU budget (2 maps failed,
  // against 1 at 1, 10 and 15).
  int stall_patience = 15;
  // Added: step cap when cMCF runs as a fallback of the Willmore flow: cheap per step (one V×V factorisation), so
  // it is run (nearly) to convergence as Kazhdan et al. do.
  int fallback_max_steps = 200;
  bool operator==(const CmcfOptions&) const = default;
};

// Added: the linear method (docs/design/spherical-map.md §8.2; linear_map.hpp).
struct LinearMapOptions {
  // Cot weights below min_weight × mean |w| are raised to it: all weights positive ⇒ Tutte/Floater embedding.
  double min_weight = 1e-3;
  // Use the clamped weights even when the plain cot map is a planar embedding (the chain's second linear attempt:
  // a plain map can still fail on the sphere, e.g. near-180° angles whose flat chord triangles face the origin).
  bool always_clamp = false;
  bool operator==(const LinearMapOptions&) const = default;
};

struct MapVerificationThresholds {
  // A sphere triangle is NUMERICALLY degenerate when its orientation cannot be trusted in double precision: the
  // flip test's determinant ((u_b − u_a)×(u_c − u_a))·(u_a + u_b + u_c) = 6·volume carries a rounding error of a
  // few ulps (ε ≈ 1.1e-16) times the edge lengths, so its sign is reliable only while the triangle's smallest
  // height h = 2·area/(longest edge) is well above ε on the unit sphere. Faces with h < degenerate_height (≈ 90 ε:
  // one more rounding of the coordinates — a Möbius map, a renormalisation — could carry the apex across the
  // opposite edge) count as degenerate. A merely TINY triangle is no failure: conformal maps compress long
  // protrusions exponentially, and areas of 1e-15…1e-25 with heights ≫ ε are exact, bijective parts of the maps of
  // armadillo, bunny, cactus, bull; the smallest area is reported as min_face_area.
  double degenerate_height = 1e-14;
  // Optional absolute floor kept for callers that want one: area below this * 4*pi also counts as degenerate
  // (0 = off; it was 1e-12, which flagged exact, bijective maps of long shapes).
  double degenerate_area = 0;
  // Quasi-conformal ratio K (p99) above this makes the verdict "distorted"; it fails verification only with
  // strict_conformal_bound (real segmentation meshes with thin necks get bijective maps with K p99 ~ 10–100).
  double max_conformal_p99 = 5.0;
  bool strict_conformal_bound = false;
  bool operator==(const MapVerificationThresholds&) const = default;
};

struct SphericalMapOptions {
  MapMethod method = MapMethod::Willmore;
  WillmoreOptions willmore;
  CmcfOptions cmcf;
  LinearMapOptions linear;
  LinearSolverKind solver = LinearSolverKind::Cholmod;
  bool fallback = true;              // on failure: more steps, the filtered flow, cMCF, the linear method (§7)
  // Added: before verification, relax the few vertices around flipped / numerically degenerate faces (untangle.hpp).
  bool untangle = true;
  MapVerificationThresholds verification;
  // Added: the operator behind every Laplacian and mass of the flows, the Poisson step, cMCF and the linear map
  // (intrinsic_laplacian.hpp: mollified lengths + intrinsic Delaunay by default).
  geometry::IntrinsicOptions laplacian;
  // Added: time budget of the FLOW attempts, in CPU seconds of the calling thread (cpu_budget.hpp: load on the
  // machine does not change which method a mesh ends on) per 10,000 vertices (at least this many seconds). It is
  // checked before every step try, including the retries of a rejected step (halved τ). When it has passed, the
  // running flow stops (FlowStop::TimeBudget) and its map is verified: a bijective one is the answer (Ok,
  // distortion in the verdict); no further flow starts, an Ok map already held (a provisional, repaired one) ends
  // the chain, and without an Ok map only the linear attempts run (bijectivity before time). Every attempt the
  // budget skips is listed in SphericalMapResult::skipped_for_budget. 0 = no budget. The request deadline
  // (Deadline) is separate, hard and wall-clock.
  // 2 s of the 3 s per 10K vertices of issue 11 (chain_budget_seconds): the other 1 s is for one step try past the
  // budget, the repair and verification of the flow's map and, without an Ok map, the linear attempts. Measured
  // (bench/map_collection_bench, CPU s): the linear attempt 0.21 s on camel (9.8K vertices); the whole chain at most
  // 2.42 s per 10K vertices over the 43 shared genus-0 meshes (diplodocus; the baseline chain reached 3.30 on man).
  double flow_budget_seconds = 2.0;
  // Added: CPU budget of the WHOLE chain per 10,000 vertices (as above): flows, local repair (untangling),
  // verification and fallbacks, so the final answer comes within it (issue 11: ≤ 3 s per 10K vertices on one core).
  // The flows stop at their own budget or at this one less linear_reserve_seconds, whichever comes first. The
  // repair of a flow's map stops when this budget less linear_reserve_seconds is spent (a linear map's repair may
  // use the rest); a map it leaves with flips fails verification, as without the repair (reported per attempt
  // in repair_budget_stopped). Measured before it: 4.86 CPU s on a 10K-vertex UroCell mitochondrion, 2.3 s of it the
  // repair after a budget-stopped flow. Without an Ok map the linear attempts still run once it is spent
  // (bijectivity before time). 0 = no chain budget.
  double chain_budget_seconds = 3.0;
  // Added: CPU seconds per 10,000 vertices kept for the linear fallback while no Ok map is held (two V×V solves and
  // the repair of their map; measured 0.04–0.36 CPU s on 10K-vertex UroCell mitochondria, 0.21 s on camel).
  double linear_reserve_seconds = 0.4;
  // Added (beyond the paper): an area-aware correction of the returned map when it is Ok (density_equalizing.hpp):
  // none (default: the paper's conformal map) or the density-equalising flow. The corrected map is re-verified
  // (bijectivity: flips, degeneracy, degree); `quality` then describes the corrected map, and the conformal
  // distortion bound (strict_conformal_bound) applies to the conformal map before the correction.
  AreaCorrectionOptions area_correction;
  // Added: an Ok map made by `method` is kept against any other method's Ok map, whatever their distortion, and
  // the chain then runs only that method's later attempts. Set for a model whose off-recipe policy refuses other
  // methods' maps (pipeline.cpp options_for_recipe): for it a bijective map by its own method is an answer and
  // another method's is a refusal. Off: the least distorted Ok map wins. Not part of the recipe (derived from its
  // policy), so not in the model file.
  bool prefer_method = false;
  bool operator==(const SphericalMapOptions&) const = default;
};

// Figures of one sphere map, compared with the input mesh.
struct MapQuality {
  long flipped_faces = 0;            // must be 0 for a bijective map
  long degenerate_faces = 0;
  int degree = 0;                    // signed sphere area / 4*pi rounded; +1 for an orientation-preserving cover
  double min_face_area = 0;          // smallest spherical triangle area (unit sphere)
  double min_face_height = 0;        // Added: smallest 2·area/(longest edge) (unit sphere); see degenerate_height
  double conformal_mean = 0, conformal_p99 = 0, conformal_max = 0;  // per-face K = sigma1/sigma2 >= 1
  double area_distortion = 0;        // exp(mean |log(area ratio)|), areas normalised to equal totals
  double roundness = 0;              // std(r)/mean(r) of the flowed surface before projection
  double mobius_centroid = 0;        // |sum w_i u_i| after Möbius balancing
  long non_finite_vertices = 0;      // NaN/Inf sphere positions (any > 0 fails verification)
  int mobius_iterations = 0;         // iterations of the area-centre balancing
  // Added: vertices moved by the local repair of a few flipped / numerically degenerate faces (untangle.hpp);
  // 0 when the map verified as computed.
  long repaired_vertices = 0;
  MapVerdict verdict = MapVerdict::Failed;  // Added: good / distorted / failed (see MapVerdict)
  long skipped_input_faces = 0;      // Added: zero-area input faces left out of the K / area statistics
};

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

enum class MapStatus { Ok, NotConverged, VerificationFailed, SolverFailed };
const char* to_string(MapStatus status);

// One entry of the fallback chain (plan_attempts()).
struct MapAttemptPlan {
  MapMethod method = MapMethod::Willmore;
  bool filtered = false;
  int max_steps = 0;
  int continue_from = -1;  // Willmore: continue the flowed surface of this earlier attempt (if it hit its cap)
  bool clamp = false;      // linear: always use the clamped (all-positive) weights
  bool operator==(const MapAttemptPlan&) const = default;
};

// The chain for `options`, ordered by cost (docs/design/spherical-map.md §7): the requested method, then (with fallback)
// more steps of the same flow, cMCF run to its stall, the linear map with intrinsic weights, the clamped
// (Tutte) linear map. Attempts that cannot help are skipped at run time (see compute_spherical_map).
std::vector<MapAttemptPlan> plan_attempts(const SphericalMapOptions& options);

// One try of one method (the first try and each fallback).
struct MapAttempt {
  MapMethod method = MapMethod::Willmore;
  bool filtered = false;
  int max_steps = 0;
  MapStatus status = MapStatus::Ok;
  MapCheck failed_check = MapCheck::None;
  FlowStop stop = FlowStop::None;    // Added: why the flow stopped
  std::string message;
  MapQuality quality;
  geometry::IntrinsicStats operator_stats;  // Added: mollification / flips of the operator this attempt used
  std::vector<FlowStepRecord> steps;
  double seconds = 0;
  double cpu_seconds = 0;            // Added: CPU seconds of the calling thread (what the flow budget counts)
  double repair_cpu_seconds = 0;     // Added: of which the local repair (untangling) of the map
  bool repair_budget_stopped = false;  // Added: the repair stopped because the chain budget was spent
  // Added: the flowed surface came out inside out (negative signed volume; cMCF through a flat state) and was
  // mirrored before the radial projection (spherical_map.cpp run_attempt).
  bool everted = false;
  bool hit_step_cap = false;         // Added: the flow ran out of steps (so "more steps" may help)
  bool map_verified = false;         // Added: the map passed verification (it may still be NotConverged)
  int continued_from = -1;           // Added: index of the attempt whose flowed surface this one continued
};

struct SphericalMapResult {
  Eigen::MatrixX3d sphere;           // #V by 3 unit vectors: the image of each input vertex
  MapStatus status = MapStatus::Ok;  // of the attempt whose map is returned
  MapCheck failed_check = MapCheck::None;
  MapVerdict verdict = MapVerdict::Failed;  // Added: quality.verdict of the returned map
  MapQuality quality;
  MapMethod method_used = MapMethod::Willmore;
  // In order. `sphere` is the map of attempts[chosen_attempt]: the Ok attempt of lowest K p99 (the chain stops at
  // the first Ok attempt that is not a repaired, distorted one), or,
  // when none is Ok, the least-bad one — a verified map of a not-converged flow first (lowest K p99), else the one
  // with the fewest non-finite, flipped and degenerate faces — with that attempt's (not Ok) status.
  std::vector<MapAttempt> attempts;
  int chosen_attempt = 0;            // Added
  // Added: the operator of the returned map's attempt (mollification epsilon, zero-area faces, negative weights
  // before, flips done).
  geometry::IntrinsicStats operator_stats;
  // Added: planned attempts of the chain that did not run because the flow budget was spent, in plan order; the
  // running flow's own stop is its attempt's FlowStop::TimeBudget, a repair's stop its attempt's
  // repair_budget_stopped. Empty when the budget stopped nothing.
  std::vector<MapAttemptPlan> skipped_for_budget;
  // Added: the area-aware correction of the returned map (stop NotRun when options.area_correction is none or the
  // map is not Ok).
  AreaCorrectionReport area_correction;
  double seconds = 0;
  double cpu_seconds = 0;            // Added: CPU seconds of the calling thread for the whole chain
  bool ok() const { return status == MapStatus::Ok; }
};

// Never throws for numerical trouble (that is a status); throws TimeoutError when `deadline` passes
// between flow steps, and InvalidInputError for meshes that violate the preconditions.
SphericalMapResult compute_spherical_map(const Mesh& mesh, const SphericalMapOptions& options = {},
                                         const Deadline& deadline = {});

}  // namespace wish
