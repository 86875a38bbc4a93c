#pragma once
// The one-ring of every vertex of a closed manifold triangle mesh, in counter-clockwise order seen from outside
// (the faces are CCW: face (a, b, c) puts b before c around a). For the repairs that need a vertex's star as a
// polygon (star_kernel_repair.hpp).

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace wish::spherical {

// nullopt when some vertex's faces do not close into one fan (not a closed manifold there) or it has fewer than 3.
std::optional<std::vector<std::vector<int>>> ordered_one_rings(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count);

}  // namespace wish::spherical
