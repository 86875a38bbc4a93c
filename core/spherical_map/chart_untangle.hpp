#pragma once
// Untangling of a few flipped / numerically degenerate sphere faces by minimising a foldover-free energy in a
// stereographic chart (Garanzha, Kaporin, Kudryavtseva, Protais, Ray, Sokolov 2021, "Foldover-free maps in 50 lines
// of code", ACM TOG 40(4)). Measured on real segmentation meshes (UroCell organelles, issue 11): the flips left by
// the flows are isolated sliver triangles with an input angle of 178–179.5° whose obtuse vertex lands on the wrong
// side of the great circle through the other two; the uniform spherical Tutte relaxation (untangle.hpp) cannot fix
// them when the patch boundary is not convex. The untangling energy can: it is finite for inverted triangles and
// becomes a barrier as its regularisation ε → 0, so it drives every triangle of the patch to positive orientation
// whenever a foldover-free placement with the fixed boundary exists.
//
// Per cluster of bad faces (connected after growing `rings` rings around their vertices):
//  * chart: stereographic projection from the antipode of the cluster centre c (conformal, orientation-preserving,
//    nearly isometric on a small cluster; the chord flip test of measure_map equals the sign of det(a, b, c), the
//    spherical orientation, which for a small triangle near c is the orientation of its chart image);
//  * free vertices: the cluster's; fixed: the other vertices of the faces touching it;
//  * energy: Σ_t f_ε(J_t), f_ε(J) = ‖J‖²_F / χ(det J, ε), χ(D, ε) = (D + √(ε² + D²)) / 2, with J_t the Jacobian of
//    the affine map reference triangle → chart triangle. f = K + 1/K for a conformal-ratio K when det J > 0, so the
//    minimiser is the least quasi-conformal placement: the reference is the INPUT triangle (the map stays as
//    conformal as it can), scaled to the cluster's mean chart area; input triangles too thin to serve (aspect
//    quality below min_reference_quality, e.g. the 179° slivers and zero-area faces) are replaced by the
//    equilateral triangle, so their images open up and their orientation is robust in double precision;
//  * minimisation: projected Newton on all free vertices at once (analytic element gradient and Hessian, the
//    Hessian's negative eigenvalues clamped per element, sparse LDLᵀ, backtracking line search; the paper uses
//    L-BFGS — a cluster has at most a few thousand unknowns, where Newton needs far fewer iterations), with ε updated
//    between steps by the rule of the paper:
//    σ = max(1 − E/E_prev, 0.1), μ = (1 − σ) χ(D_min, ε), ε ← 2√(μ(μ − D_min)) while D_min < μ;
//  * stop: every face touching the cluster passes the sphere tests (flip, degenerate height); else the cluster is
//    restored, grown and retried up to max_grow times.
// The caller re-verifies the whole map; untouched clusters and the rest of the map keep their positions.
// Bounded by `budget` (the map chain's CPU budget, issue 11; measured before it: 2.3 CPU s on two 10K-vertex UroCell
// mitochondria after a budget-stopped flow): checked before every cluster try and every ε update. When it is spent,
// the cluster being solved is restored, no further cluster is tried and budget_stopped is set; clusters fixed
// before stay fixed. The remaining bad faces are counted as usual and fail the caller's verification.

#include <Eigen/Core>

#include "core/common/cpu_budget.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish::spherical {

struct ChartUntangleOptions {
  int rings = 2;                        // initial cluster: bad faces' vertices plus this many rings
  int grow_rings = 2;                   // rings added per retry
  int max_grow = 4;                     // retries per cluster
  int max_cluster_vertices = 3000;      // larger clusters are left to the caller's other fallbacks
  // A map with more bad faces than this fraction is not "a few flips" but a failed flow (measured: 2000–3000 flips
  // on two UroCell mitochondria, where trying every cluster cost 5–7 CPU s): left to the next method of the chain.
  double max_bad_fraction = 0.01;
  double max_chart_angle = 2.6;         // radians: a cluster reaching farther from its centre is skipped (chart
                                        // scale 1/(1 + cos θ): ≤ 13× the centre's at 2.6 rad)
  int max_iterations = 60;              // ε updates (outer iterations) per try
  int newton_steps_per_iteration = 2;   // projected-Newton steps at fixed ε
  double min_reference_quality = 0.05;  // 4√3·area / Σℓ² (1 = equilateral) below which the reference is equilateral
};

struct ChartUntangleResult {
  long bad_faces_before = 0, bad_faces_after = 0;  // flipped or numerically degenerate (whole map)
  long clusters = 0, clusters_fixed = 0;
  long moved_vertices = 0;
  bool budget_stopped = false;  // the CPU budget ran out with clusters left unsolved
};

// `sphere` (V×3 unit vectors) is modified in place only in clusters that end free of bad faces.
ChartUntangleResult untangle_in_charts(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                                       const Eigen::MatrixX3i& faces, const MapVerificationThresholds& thresholds,
                                       const ChartUntangleOptions& options = {},
                                       const CpuBudget& budget = {});

}  // namespace wish::spherical
