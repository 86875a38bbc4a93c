#pragma once
// The check every demo mesh must pass before it is written: closed (each edge in exactly two faces, in
// opposite directions), vertex-manifold, one component, Euler characteristic 2 (genus 0), outward
// (positive signed volume), no degenerate triangles. Self-contained so the generator does not depend on the
// validation area; the tests also run core/validation's prepare_for_mapping on the output.

#include <cstdint>
#include <string>

#include "core/mesh/mesh.hpp"

namespace wish::volume {

struct SurfaceTopology {
  std::int64_t vertices = 0, edges = 0, faces = 0, components = 0;
  std::int64_t bad_edges = 0;          // not shared by exactly two oppositely oriented faces
  std::int64_t nonmanifold_vertices = 0;
  std::int64_t degenerate_faces = 0;
  std::int64_t euler = 0;
  double signed_volume = 0;
  bool closed_genus0() const {
    return bad_edges == 0 && nonmanifold_vertices == 0 && degenerate_faces == 0 && components == 1 && euler == 2 &&
           signed_volume > 0;
  }
  std::string describe() const;
};

SurfaceTopology analyze_surface(const Mesh& mesh);

}  // namespace wish::volume
