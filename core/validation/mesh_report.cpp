// analyze_mesh: topology (edge_topology.cpp) plus the geometric and duplicate counts of the report.
#include "core/validation/mesh_report.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <unordered_set>

#include <Eigen/Geometry>

#include "core/validation/edge_topology.hpp"
#include "core/validation/position_key.hpp"

namespace wish {

MeshReport analyze_mesh(const Mesh& mesh) {
  using validation_detail::is_proper_face;
  MeshReport r;
  const Eigen::Index nv = mesh.vertex_count(), nf = mesh.face_count();
  r.vertices = nv;
  r.faces = nf;
  const auto t = validation_detail::compute_edge_topology(mesh.faces, nv);
  r.edges = t.edges;
  r.components = t.components;
  r.boundary_edges = t.boundary_edges;
  r.nonmanifold_edges = t.nonmanifold_edges;
  r.nonmanifold_vertices = t.nonmanifold_vertices;
  r.misoriented_edges = t.misoriented_edges;
  r.orientation_consistent = t.misoriented_edges == 0;
  r.euler_characteristic = t.referenced_vertices - t.edges + t.proper_faces;
  if (t.boundary_edges == 0 && t.nonmanifold_edges == 0 && t.nonmanifold_vertices == 0 && t.components == 1 &&
      r.euler_characteristic <= 2 && r.euler_characteristic % 2 == 0)
    r.genus = (2 - r.euler_characteristic) / 2;

  // Referenced vertices (by any face with in-range indices) and the bounding box over them.
  std::vector<char> referenced(static_cast<std::size_t>(nv), 0);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.faces(f, k) >= 0 && mesh.faces(f, k) < nv) referenced[static_cast<std::size_t>(mesh.faces(f, k))] = 1;
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (Eigen::Index v = 0; v < nv; ++v) {
    if (!referenced[static_cast<std::size_t>(v)]) {
      ++r.unreferenced_vertices;
      continue;
    }
    lo = lo.cwiseMin(mesh.vertices.row(v));
    hi = hi.cwiseMax(mesh.vertices.row(v));
  }
  if (r.unreferenced_vertices < nv)
    for (int k = 0; k < 3; ++k) {
      r.bbox_min[static_cast<std::size_t>(k)] = lo[k];
      r.bbox_max[static_cast<std::size_t>(k)] = hi[k];
    }

  // Volume about the origin, literally as the header defines it (for an open mesh it depends on the origin).
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double volume6 = 0, area2 = 0;
  std::unordered_set<std::array<int, 3>, validation_detail::TripleHash> seen_faces;
  seen_faces.reserve(static_cast<std::size_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (!is_proper_face(mesh.faces, f, nv)) {
      ++r.degenerate_faces;
      continue;
    }
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)).transpose() - centre,
                          b = mesh.vertices.row(mesh.faces(f, 1)).transpose() - centre,
                          c = mesh.vertices.row(mesh.faces(f, 2)).transpose() - centre;
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.squaredNorm() == 0) {  // exactly zero area: collinear or coincident corners
      ++r.degenerate_faces;
      ++r.zero_area_faces;
    }
    area2 += n.norm();
    volume6 += a.dot(b.cross(c));
    std::array<int, 3> key{mesh.faces(f, 0), mesh.faces(f, 1), mesh.faces(f, 2)};
    std::sort(key.begin(), key.end());
    if (!seen_faces.insert(key).second) ++r.duplicate_faces;
  }
  r.signed_volume = volume6 / 6;
  r.area = area2 / 2;

  std::unordered_set<validation_detail::PositionKey, validation_detail::PositionHash> seen_positions;
  seen_positions.reserve(static_cast<std::size_t>(nv));
  for (Eigen::Index v = 0; v < nv; ++v)
    if (!seen_positions.insert(validation_detail::position_key(mesh.vertices, v)).second) ++r.duplicate_vertices;
  return r;
}

}  // namespace wish
