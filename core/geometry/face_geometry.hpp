#pragma once
// Per-face geometry of a triangle mesh (libigl conventions: faces CCW seen from outside).
// Units: lengths in the mesh's units, areas in units², angles in radians.

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"

namespace wish::geometry {

// A_f = ½‖(x1−x0)×(x2−x0)‖ per face.
Eigen::VectorXd face_areas(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

// Corner cotangents: column k of row f is cot of the angle at corner k of face f, cot θ = (u·v)/‖u×v‖ with u, v the
// two edges leaving the corner. A zero-area face gives ±inf/NaN here; callers that can meet such faces check.
Eigen::MatrixX3d corner_cotangents(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

// Corner angles in radians (same layout as corner_cotangents).
Eigen::MatrixX3d corner_angles(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

// Signed volume (1/6) Σ_f x0·(x1×x2); positive for a closed, outward-oriented mesh.
double signed_volume(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

// Mean length over the three edges of every face (interior edges counted twice, which is what a mean over
// half-edges means; fine as a length scale).
double mean_edge_length(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

}  // namespace wish::geometry
