#pragma once
// Evaluating a descriptor's SH surface x_L(u) = sum_j c_j Y_j(u) (paper Eq. 9) at sphere points: on a subdivided
// icosahedron (the paper's reconstruction, levels 0..7) or at the input's own sphere map with its connectivity.
// Only the real part is kept (c_l^{-m} = (-1)^m conj(c_l^m) for a real surface; other coefficients are projected).

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"
#include "core/sh/sh_descriptor.hpp"

namespace wish {

// n x 3 positions x_L(u_i) at the rows u_i (non-zero directions) of `sphere_points`.
Eigen::MatrixX3d evaluate_sh_surface(const ShDescriptor& descriptor, const Eigen::MatrixX3d& sphere_points);

// The SH surface on make_icosphere(level) (outward orientation kept); level in [0, 7], InvalidInputError otherwise.
Mesh reconstruct_on_icosphere(const ShDescriptor& descriptor, int level);

// The SH surface at the given sphere points with the given faces (e.g. the input mesh's connectivity).
Mesh reconstruct_on_mesh(const ShDescriptor& descriptor, const Eigen::MatrixX3d& sphere_points,
                         const Eigen::MatrixX3i& faces);

}  // namespace wish
