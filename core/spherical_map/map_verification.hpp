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

#include "core/spherical_map/spherical_map.hpp"

namespace wish::spherical {

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

// First failed check in the order non_finite, flipped_faces, degenerate_faces, degree, and — only with
// strict_conformal_bound — conformal_distortion; MapCheck::None when the map passes.
// The per-face sphere test of measure_map(), for the repairs (untangle, chart_untangle): face f is flipped (its chord
// triangle does not face away from the origin, i.e. det(a, b, c) <= 0) or numerically degenerate (height below
// min_height).
bool is_bad_sphere_face(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces, Eigen::Index f, double min_height);

MapCheck failed_map_check(const MapQuality& quality, const MapVerificationThresholds& thresholds);

}  // namespace wish::spherical
