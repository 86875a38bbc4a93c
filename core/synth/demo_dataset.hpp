#pragma once
// The committed, deterministic generator of the SYNTHETIC demo set (issue 5, docs/design/classification.md): nucleus-like
// shapes of the paper's six classes, meshed like segmentation output — shape -> binary label volume on a fixed
// voxel grid -> largest component, cavities filled -> marching tetrahedra -> light Taubin smoothing — giving
// irregular triangles and a few thousand vertices. Every mesh is verified closed, manifold, one component,
// genus 0 and outward; a shape whose voxelisation fails the check is redrawn with the next sub-seed (at most
// max_attempts), so the result stays a pure function of (seed, class, index).

#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/synth/nucleus_shape.hpp"
#include "core/volume/surface_topology.hpp"

namespace wish::synth {

struct DemoOptions {
  int per_class = 16;
  std::uint64_t seed = 1;
  double voxel_size = 0.33;       // µm: the label grid (the same for all shapes, as one segmented volume)
  int smoothing_iterations = 8;   // Taubin lambda|mu pairs
  int max_attempts = 8;
};

struct DemoMesh {
  std::string label;   // class name
  std::string name;    // "<label>_<index, 3 digits>"
  Mesh mesh;           // µm
  int attempts = 1;
  volume::SurfaceTopology topology;
};

// Throws InvalidInputError("generation_failed") when no attempt gives a closed genus-0 surface.
DemoMesh generate_demo_nucleus(int class_index, int index, const DemoOptions& options);
std::vector<DemoMesh> generate_demo_set(const DemoOptions& options);

}  // namespace wish::synth
