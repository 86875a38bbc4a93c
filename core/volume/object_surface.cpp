#include "core/volume/object_surface.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "core/volume/binary_volume.hpp"
#include "core/volume/decimation.hpp"
#include "core/volume/marching_tetrahedra.hpp"
#include "core/volume/surface_topology.hpp"
#include "core/volume/taubin_smoothing.hpp"

namespace wish::volume {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::int64_t count_foreground(const BinaryVolume& v) {
  std::int64_t n = 0;
  for (auto l : v.labels) n += l;
  return n;
}

// Genus of a closed, oriented, one-component surface; -1 when it is not one.
int genus_of(const SurfaceTopology& t) {
  if (t.bad_edges != 0 || t.nonmanifold_vertices != 0 || t.components != 1 || (2 - t.euler) % 2 != 0) return -1;
  return static_cast<int>((2 - t.euler) / 2);
}

std::string fmt(const char* format, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

// Largest piece and cavities filled; adds the repairs.
void clean(BinaryVolume& box, std::vector<std::string>& repairs) {
  const std::int64_t before = count_foreground(box);
  const int pieces = keep_largest_component(box);
  const std::int64_t kept = count_foreground(box);
  if (pieces > 1)
    repairs.push_back(fmt("kept the largest of %.0f pieces (dropped %.0f voxels)", pieces, static_cast<double>(before - kept)));
  const int cavities = fill_cavities(box);
  if (cavities > 0)
    repairs.push_back(fmt("filled %.0f internal cavities (%.0f voxels)", cavities, static_cast<double>(count_foreground(box) - kept)));
}

}  // namespace

double mesh_area(const Mesh& m) {
  double a = 0;
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3d p = m.vertices.row(m.faces(f, 0)), q = m.vertices.row(m.faces(f, 1)), r = m.vertices.row(m.faces(f, 2));
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

double mesh_volume(const Mesh& m) {
  double v = 0;
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3d p = m.vertices.row(m.faces(f, 0)), q = m.vertices.row(m.faces(f, 1)), r = m.vertices.row(m.faces(f, 2));
    v += p.dot(q.cross(r)) / 6;
  }
  return v;
}

ObjectSurface object_surface(const LabelImage& image, const ObjectSet& objects, const VolumeObject& object,
                             const SurfaceOptions& options) {
  ObjectSurface out;
  auto t0 = Clock::now();
  const int pad = 1 + (options.close_handles ? std::max(0, options.max_closing_radius) : 0);
  BinaryVolume box;
  std::int64_t box_voxels = 1;
  for (int k = 0; k < 3; ++k) {
    box.dims[k] = static_cast<int>(object.bbox_max[k] - object.bbox_min[k] + 1 + 2 * pad);
    box_voxels *= box.dims[k];
    box.origin(k) = static_cast<double>(object.bbox_min[k] - pad) * image.spacing(k);
  }
  if (box_voxels > options.max_box_voxels) {
    out.refusal_code = "box_too_large";
    out.refusal = fmt("padded bounding box of %.0f voxels exceeds the limit of %.0f", static_cast<double>(box_voxels),
                      static_cast<double>(options.max_box_voxels));
    return out;
  }
  box.spacing = image.spacing;
  box.labels.assign(static_cast<std::size_t>(box_voxels), 0);
  for (int z = pad; z < box.dims[2] - pad; ++z)
    for (int y = pad; y < box.dims[1] - pad; ++y)
      for (int x = pad; x < box.dims[0] - pad; ++x) {
        const std::size_t i = image.index(object.bbox_min[0] + x - pad, object.bbox_min[1] + y - pad, object.bbox_min[2] + z - pad);
        box.labels[box.index(x, y, z)] = objects.id_at(image, i) == object.id;
      }
  clean(box, out.repairs);
  out.timings.extraction = seconds_since(t0);

  t0 = Clock::now();
  Mesh mesh = marching_tetrahedra(box);
  SurfaceTopology topology = analyze_surface(mesh);
  out.genus = genus_of(topology);
  if (out.genus > 0 && options.close_handles) {
    for (int r = 1; r <= options.max_closing_radius; ++r) {
      BinaryVolume closed = box;
      const std::int64_t added = morphological_close(closed, r);
      std::vector<std::string> notes;
      clean(closed, notes);
      Mesh candidate = marching_tetrahedra(closed);
      const SurfaceTopology t = analyze_surface(candidate);
      if (genus_of(t) == 0) {
        out.repairs.push_back(fmt("morphological closing of radius %.0f (+%.0f voxels) removed genus %.0f", r,
                                  static_cast<double>(added), out.genus));
        for (auto& n : notes) out.repairs.push_back("after closing: " + n);
        box = std::move(closed);
        mesh = std::move(candidate);
        topology = t;
        break;
      }
    }
  }
  out.voxels_meshed = count_foreground(box);
  out.voxel_volume = static_cast<double>(out.voxels_meshed) * image.spacing.prod();
  out.raw_area = mesh_area(mesh);
  out.raw_volume = mesh_volume(mesh);
  out.timings.surface = seconds_since(t0);
  const int final_genus = genus_of(topology);
  if (final_genus != 0) {
    out.mesh = std::move(mesh);
    if (final_genus < 0) {
      out.refusal_code = "not_manifold";
      out.refusal = "the voxel surface is not one closed manifold (" + topology.describe() + ")";
    } else {
      out.refusal_code = "genus_nonzero";
      out.refusal = fmt("the surface has genus %.0f (%.0f handle(s)); WISH maps genus-0 surfaces only", final_genus, final_genus);
      if (options.close_handles)
        out.refusal += fmt("; closing up to radius %.0f did not remove them", options.max_closing_radius);
    }
    return out;
  }

  t0 = Clock::now();
  if (options.smoothing_iterations > 0) {
    taubin_smooth(mesh, options.smoothing_iterations, options.taubin_lambda, options.taubin_mu);
    const double v = mesh_volume(mesh);
    if (v > 0 && out.raw_volume > 0) {
      // Uniform scale about the centroid restoring the pre-smoothing volume (Taubin keeps it only approximately).
      const Eigen::RowVector3d c = mesh.vertices.colwise().mean();
      const double s = std::cbrt(out.raw_volume / v);
      mesh.vertices = ((mesh.vertices.rowwise() - c) * s).rowwise() + c;
    }
  }
  out.timings.smoothing = seconds_since(t0);

  t0 = Clock::now();
  out.vertices_before_decimation = mesh.vertex_count();
  const DecimationResult d = decimate_to_vertices(mesh, options.target_vertices);
  out.timings.decimation = seconds_since(t0);
  topology = analyze_surface(mesh);
  if (!topology.closed_genus0()) {
    out.refusal_code = d.collapses > 0 ? "decimation_failed" : "not_manifold";
    out.refusal = std::string(d.collapses > 0 ? "decimation" : "smoothing") +
                  " left a surface that is not closed genus 0 (" + topology.describe() + ")";
    out.mesh = std::move(mesh);
    return out;
  }
  out.area = mesh_area(mesh);
  out.volume = mesh_volume(mesh);
  out.mesh = std::move(mesh);
  out.ok = true;
  return out;
}

}  // namespace wish::volume
