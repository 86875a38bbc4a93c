#pragma once
// Angle-weighted vertex normals (Thürmer & Wüthrich 1998; libigl PER_VERTEX_NORMALS_WEIGHTING_TYPE_ANGLE):
// N_i = normalise(Σ_{f∋i} θ_{f,i} n_f), outward for CCW faces. A vertex with no incident area gets (0,0,0).

#include <Eigen/Core>

namespace wish::geometry {

Eigen::MatrixX3d vertex_normals(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

}  // namespace wish::geometry
