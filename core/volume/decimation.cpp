#include "core/volume/decimation.hpp"

#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "core/common/errors.hpp"
#include "core/volume/link_condition.hpp"

namespace wish::volume {
namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  HalfedgeAttributes(OpenMesh::Attributes::Status);
};
// OpenMesh's mesh with the decimater's link condition answered by collapse_keeps_manifold (link_condition.hpp: the
// same answer, without the assertion-laden library call). BaseDecimaterT::is_collapse_legal calls
// mesh_.is_collapse_ok on the mesh type it is given, so this one hides the library's.
struct OMesh : OpenMesh::TriMesh_ArrayKernelT<DoubleTraits> {
  bool is_collapse_ok(HalfedgeHandle v0v1) const { return collapse_keeps_manifold(*this, v0v1); }
};

}  // namespace

DecimationResult decimate_to_vertices(Mesh& mesh, std::int64_t target_vertices, double max_normal_deviation_degrees) {
  DecimationResult r;
  r.vertices_before = r.vertices_after = mesh.vertex_count();
  if (target_vertices <= 0 || mesh.vertex_count() <= target_vertices) return r;
  OMesh om;
  std::vector<OMesh::VertexHandle> handles;
  handles.reserve(static_cast<std::size_t>(mesh.vertex_count()));
  for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i)
    handles.push_back(om.add_vertex(OMesh::Point(mesh.vertices(i, 0), mesh.vertices(i, 1), mesh.vertices(i, 2))));
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    const auto fh = om.add_face(handles[mesh.faces(f, 0)], handles[mesh.faces(f, 1)], handles[mesh.faces(f, 2)]);
    if (!fh.is_valid())
      throw WishError(ErrorCategory::Internal, "decimation_failed",
                      "face " + std::to_string(f) + " could not be added to the half-edge mesh (not manifold)");
  }
  om.update_face_normals();
  using Decimater = OpenMesh::Decimater::DecimaterT<OMesh>;
  Decimater decimater(om);
  OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<OMesh>::Handle flipping;
  decimater.add(quadric);
  decimater.add(flipping);
  decimater.module(quadric).unset_max_err();  // binary: collapse by cost until the target is reached
  decimater.module(flipping).set_max_normal_deviation(max_normal_deviation_degrees);
  if (!decimater.initialize()) throw WishError(ErrorCategory::Internal, "decimation_failed", "decimater did not initialise");
  r.collapses = static_cast<std::int64_t>(decimater.decimate_to(static_cast<std::size_t>(target_vertices)));
  om.garbage_collection();
  mesh.vertices.resize(static_cast<Eigen::Index>(om.n_vertices()), 3);
  for (const auto vh : om.vertices()) {
    const auto& p = om.point(vh);
    mesh.vertices.row(vh.idx()) << p[0], p[1], p[2];
  }
  mesh.faces.resize(static_cast<Eigen::Index>(om.n_faces()), 3);
  for (const auto fh : om.faces()) {
    int k = 0;
    for (const auto vh : om.fv_range(fh)) mesh.faces(fh.idx(), k++) = vh.idx();
  }
  r.vertices_after = mesh.vertex_count();
  return r;
}

}  // namespace wish::volume
