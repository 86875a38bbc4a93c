#include "core/volume/object_surface.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "core/common/elapsed.hpp"
#include "core/volume/binary_volume.hpp"
#include "core/volume/decimation.hpp"
#include "core/volume/marching_tetrahedra.hpp"
#include "core/volume/surface_topology.hpp"
#include "core/volume/taubin_smoothing.hpp"

namespace wish::volume {
namespace {

using Clock = std::chrono::steady_clock;

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

std::string format_numbers(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char buf[320];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

// Largest piece and cavities filled; adds the repairs; returns the number of pieces.
int clean(BinaryVolume& box, std::vector<std::string>& repairs) {
  const std::int64_t before = count_foreground(box);
  const int pieces = keep_largest_component(box);
  const std::int64_t kept = count_foreground(box);
  if (pieces > 1)
    repairs.push_back(format_numbers("kept the largest of %.0f pieces (dropped %.0f voxels)", pieces, static_cast<double>(before - kept)));
  const int cavities = fill_cavities(box);
  if (cavities > 0)
    repairs.push_back(format_numbers("filled %.0f internal cavities (%.0f voxels)", cavities, static_cast<double>(count_foreground(box) - kept)));
  return pieces;
}

// What was found about a genus > 0 object and what would help, for the refusal.
std::string handle_findings(const ObjectSurface& s, const SurfaceOptions& options) {
  std::string out;
  if (!s.touching_ids.empty()) {
    std::string ids;
    for (std::size_t k = 0; k < s.touching_ids.size() && k < 8; ++k) ids += (k ? ", " : "") + std::to_string(s.touching_ids[k]);
    if (s.touching_ids.size() > 8) ids += ", ...";
    out += format_numbers("; it touches %.0f other object(s) on %.0f voxels (", static_cast<double>(s.touching_ids.size()),
               static_cast<double>(s.touching_voxels)) + ids + "): objects touching in a loop make handles";
  } else {
    out += "; it touches no other object";
  }
  if (s.pieces > 1) out += format_numbers("; it has %.0f separate pieces (the largest was meshed)", s.pieces);
  out += "; the repair that removes the handles (" + s.repair.describe() + ")" +
         (options.max_repair_share > 0
              ? format_numbers(" changes more than the bound of %.2f %% (--max-repair-share %.4g or --close-handles keep it)",
                    100 * options.max_repair_share, s.repair.volume_change() * 1.0001)
              : std::string(" is not applied: handle repair is off (--no-close-handles)"));
  return out;
}

// Voxels of the object with a 6-neighbour that belongs to another object (labels touching in the segmentation).
void count_touching(const LabelImage& image, const ObjectSet& objects, const VolumeObject& object, ObjectSurface& out) {
  const std::int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  for (std::int64_t z = object.bbox_min[2]; z <= object.bbox_max[2]; ++z)
    for (std::int64_t y = object.bbox_min[1]; y <= object.bbox_max[1]; ++y)
      for (std::int64_t x = object.bbox_min[0]; x <= object.bbox_max[0]; ++x) {
        const std::size_t i = image.index(x, y, z);
        if (objects.id_at(image, i) != object.id) continue;
        bool touches = false;
        auto look = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
          if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) return;
          const std::uint32_t other = objects.id_at(image, image.index(a, b, c));
          if (other == 0 || other == object.id) return;
          touches = true;
          if (std::find(out.touching_ids.begin(), out.touching_ids.end(), other) == out.touching_ids.end())
            out.touching_ids.push_back(other);
        };
        look(x - 1, y, z), look(x + 1, y, z), look(x, y - 1, z), look(x, y + 1, z), look(x, y, z - 1), look(x, y, z + 1);
        out.touching_voxels += touches;
      }
  std::sort(out.touching_ids.begin(), out.touching_ids.end());
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
  const int pad = 2;  // the border layer stays background, with a layer for the repair's growth from it
  BinaryVolume box;
  std::int64_t box_voxels = 1;
  for (int k = 0; k < 3; ++k) {
    box.dims[k] = static_cast<int>(object.bbox_max[k] - object.bbox_min[k] + 1 + 2 * pad);
    box_voxels *= box.dims[k];
    box.origin(k) = static_cast<double>(object.bbox_min[k] - pad) * image.spacing(k);
  }
  if (box_voxels > options.max_box_voxels) {
    out.refusal_code = "box_too_large";
    out.refusal = format_numbers("padded bounding box of %.0f voxels exceeds the limit of %.0f", static_cast<double>(box_voxels),
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
  count_touching(image, objects, object, out);
  out.pieces = clean(box, out.repairs);
  out.timings.extraction = seconds_since(t0);

  t0 = Clock::now();
  Mesh mesh = marching_tetrahedra(box);
  SurfaceTopology topology = analyze_surface(mesh);
  out.genus = genus_of(topology);
  if (out.genus > 0) {
    // Measured whether or not it is kept: a refusal then says what the repair would change.
    TopologyRepair repair = remove_handles(box);
    out.repair = repair.figures;
    if (out.repair.volume_change() <= options.max_repair_share) {
      out.repaired = true;
      out.repairs.push_back("removed the handles: " + out.repair.describe());
      box = std::move(repair.result);
      mesh = marching_tetrahedra(box);
      topology = analyze_surface(mesh);
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
      out.refusal = format_numbers("the surface has genus %.0f (%.0f handle(s)); WISH maps genus-0 surfaces only", final_genus, final_genus) +
                    handle_findings(out, options);
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
