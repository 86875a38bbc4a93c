#pragma once
// Verification of a sphere map u: input mesh → S² (docs/design/spherical-map.md §7). Fills MapQuality:
//  * flipped faces: (a,b,c) inverted iff ((u_b − u_a)×(u_c − u_a))·(u_a + u_b + u_c) ≤ 0 — must be 0;
//  * degenerate faces: numerically degenerate sphere triangles, whose orientation (the flip test) is not reliable in
//    double precision: smallest height 2·area/longest edge < thresholds.degenerate_height (see there), or area
//    below the optional floor thresholds.degenerate_area · 4π;
//  * degree: Σ signed solid angles / 4π, rounded (Van Oosterom–Strackee); +1 for a bijective, orientation-
//    preserving map;
//  * conformal distortion K_f = σ₁/σ₂ ≥ 1 of the affine map input triangle → sphere triangle (mean, p99, max);
//  * area distortion exp(mean_f |log(a_f/A_f)|), areas normalised to equal totals (1 = equiareal);
//  * verdict: failed (any check but the distortion bound), good (K p99 ≤ max_conformal_p99), distorted (above).
// Input faces of (numerically) zero area have no affine map to measure: they are left out of the K and area
// figures and counted in skipped_input_faces (their sphere images are still checked for flips and degeneracy).
// Roundness and the Möbius centroid are filled by the caller (they belong to the flow and the balancing).

#include <string>

#include <Eigen/Core>

#include "core/spherical_map/map_types.hpp"

namespace wish {

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

// Figures of one sphere map, compared with the input mesh.
struct MapQuality {
  long flipped_faces = 0;            // must be 0 for a bijective map
  long degenerate_faces = 0;
  int degree = 0;                    // signed sphere area / 4*pi rounded; +1 for an orientation-preserving cover
  double min_face_area = 0;          // smallest spherical triangle area (unit sphere)
  double min_face_height = 0;        // Added: smallest 2·area/(longest edge) (unit sphere); see degenerate_height
  double conformal_mean = 0, conformal_p99 = 0, conformal_max = 0;  // per-face K = sigma1/sigma2 >= 1
  // Added: K p99 over the input faces whose every corner angle is at least kWellShapedDegrees (= conformal_p99 on a
  // mesh without needles). On decimated meshes with 2-3 % needle triangles the 99th percentile lands on the
  // needles, whose affine map is ill-conditioned (a small position error reads as a large K): this figure is
  // what the chain compares between a flow's map and a one-shot map (map_chain.cpp; docs/design/needle-flows.md).
  double conformal_p99_well_shaped = 0;
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

namespace spherical {

inline constexpr double kWellShapedDegrees = 5.0;

MapQuality measure_map(const Eigen::MatrixX3d& input_vertices, const Eigen::MatrixX3i& faces,
                       const Eigen::MatrixX3d& sphere, const MapVerificationThresholds& thresholds);

// Per-face figures behind MapQuality's summaries (what a viewer colours the map by), in face order:
//  * conformal[f] = K_f = σ₁/σ₂ ≥ 1 of the affine map input triangle → sphere chord triangle (+inf when the sphere
//    triangle is degenerate);
//  * area_ratio[f] = (a_f / Σa) / (A_f / ΣA): sphere area share over input area share (1 = equiareal);
//  * input_area[f] = A_f, the input triangle's area (in the mesh's units).
// measure_map's conformal mean / p99 / max and area distortion exp(mean |log area_ratio|) are computed from these.
struct FaceDistortion {
  Eigen::VectorXd conformal, area_ratio, input_area;
};
FaceDistortion face_distortion(const Eigen::MatrixX3d& input_vertices, const Eigen::MatrixX3i& faces,
                               const Eigen::MatrixX3d& sphere);

// The per-face sphere test of measure_map(), for the repairs (untangle, chart_untangle, star_kernel_repair): face f is
// flipped (its chord triangle does not face away from the origin, i.e. det(a, b, c) <= 0) or numerically degenerate
// (height below min_height).
bool is_bad_sphere_face(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces, Eigen::Index f, double min_height);
// The number of faces of the map that fail is_bad_sphere_face.
long count_bad_sphere_faces(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces, double min_height);

// First failed check in the order non_finite, flipped_faces, degenerate_faces, degree, and — only with
// strict_conformal_bound — conformal_distortion; MapCheck::None when the map passes.
MapCheck failed_map_check(const MapQuality& quality, const MapVerificationThresholds& thresholds);

}  // namespace spherical
}  // namespace wish
