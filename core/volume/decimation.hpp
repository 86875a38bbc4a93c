#pragma once
// Decimation of a closed manifold mesh to a target vertex count by quadric-error edge collapses (Garland & Heckbert
// 1997) with OpenMesh's decimater (Debian's libopenmesh-dev). Only collapses that pass the link condition are made
// (link_condition.hpp: OpenMesh's own test, compiled here), so a closed 2-manifold stays one and the genus does not
// change; ModNormalFlipping refuses collapses that turn a face by more than `max_normal_deviation_degrees` (no
// fold-overs).

#include <cstdint>

#include "core/mesh/mesh.hpp"

namespace wish::volume {

struct DecimationResult {
  std::int64_t vertices_before = 0, vertices_after = 0;
  std::int64_t collapses = 0;
};

DecimationResult decimate_to_vertices(Mesh& mesh, std::int64_t target_vertices, double max_normal_deviation_degrees = 45);

}  // namespace wish::volume
