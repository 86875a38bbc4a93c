#include "core/synth/demo_dataset.hpp"

#include <cmath>
#include <cstdio>

#include "core/common/errors.hpp"
#include "core/synth/synth_random.hpp"
#include "core/volume/binary_volume.hpp"
#include "core/volume/marching_tetrahedra.hpp"
#include "core/volume/taubin_smoothing.hpp"

namespace wish::synth {
namespace {

using volume::BinaryVolume;

BinaryVolume voxelise(const NucleusShape& shape, double spacing) {
  const double R = shape.bounding_radius();
  BinaryVolume v;
  v.spacing = Eigen::Vector3d::Constant(spacing);
  Eigen::Vector3d lo, hi;
  for (int k = 0; k < 3; ++k) {
    // The grid is aligned to multiples of the voxel size in world space, as one segmented volume would be.
    const double first = std::floor((shape.centre(k) - R) / spacing) - 2;
    const double last = std::ceil((shape.centre(k) + R) / spacing) + 2;
    v.origin(k) = first * spacing;
    v.dims[k] = static_cast<int>(last - first) + 1;
  }
  v.labels.assign(static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2], 0);
  for (int z = 0; z < v.dims[2]; ++z)
    for (int y = 0; y < v.dims[1]; ++y)
      for (int x = 0; x < v.dims[0]; ++x)
        v.labels[v.index(x, y, z)] = shape.inside(v.origin + spacing * Eigen::Vector3d(x, y, z)) ? 1 : 0;
  return v;
}

}  // namespace

DemoMesh generate_demo_nucleus(int class_index, int index, const DemoOptions& options) {
  const auto& classes = demo_classes();
  if (class_index < 0 || class_index >= static_cast<int>(classes.size()))
    throw InvalidInputError("invalid_parameter", "unknown demo class index " + std::to_string(class_index));
  DemoMesh out;
  out.label = classes[class_index];
  char name[64];
  std::snprintf(name, sizeof name, "%s_%03d", out.label.c_str(), index);
  out.name = name;
  std::string last_problem;
  for (int attempt = 0; attempt < options.max_attempts; ++attempt) {
    const NucleusShape shape = sample_nucleus_shape(
        class_index, mix_seed(options.seed, static_cast<std::uint64_t>(class_index) + 1,
                              static_cast<std::uint64_t>(index) * 64 + static_cast<std::uint64_t>(attempt)));
    BinaryVolume volume = voxelise(shape, options.voxel_size);
    volume::clear_border(volume);
    volume::keep_largest_component(volume);
    volume::fill_cavities(volume);
    Mesh mesh = volume::marching_tetrahedra(volume);
    volume::taubin_smooth(mesh, options.smoothing_iterations);
    const volume::SurfaceTopology topology = volume::analyze_surface(mesh);
    if (topology.closed_genus0()) {
      out.mesh = std::move(mesh);
      out.attempts = attempt + 1;
      out.topology = topology;
      return out;
    }
    last_problem = topology.describe();
  }
  throw InvalidInputError("generation_failed", "demo mesh " + out.name + ": no closed genus-0 surface in " +
                                                   std::to_string(options.max_attempts) + " attempts (last: " +
                                                   last_problem + ")");
}

std::vector<DemoMesh> generate_demo_set(const DemoOptions& options) {
  std::vector<DemoMesh> set;
  for (int i = 0; i < options.per_class; ++i)
    for (int c = 0; c < static_cast<int>(demo_classes().size()); ++c) set.push_back(generate_demo_nucleus(c, i, options));
  return set;
}

}  // namespace wish::synth
