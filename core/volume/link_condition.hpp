#pragma once
// Whether collapsing the edge v0 → v1 of a triangle mesh keeps it a 2-manifold of the same topology: the link
// condition (Dey, Edelsbrunner, Guha, Nekhayev 1999, "Topology preserving edge contraction"; Hoppe et al. 1993): the
// one-rings of v0 and v1 share no vertex but the apexes vl, vr of the edge's two triangles; plus the boundary rules
// of a mesh with holes (no triangle left hanging on two boundary edges, no interior edge between two boundary
// vertices).
//
// The decimater (decimation.cpp) asks this once per candidate collapse. It is the question OpenMesh's
// TriConnectivity::is_collapse_ok answers, asked here because Debian's libOpenMeshCore is built with its assertions
// on: there every status() access builds and compares two type-name strings, about half of a decimation's time
// (perf on SlowHardShapes, 2026-12-07: is_collapse_ok with memcmp, malloc and free). Compiled here, the accessors are
// inline and checked by nothing; and the status bits are left alone (OpenMesh's marks the one-rings `tagged`).
// tests/volume/link_condition_test.cpp checks it gives OpenMesh's answer on every halfedge through whole decimations.
//
// HalfedgeMesh: an OpenMesh triangle mesh with status attributes on vertices and edges.

namespace wish::volume {

template <class HalfedgeMesh>
bool collapse_keeps_manifold(const HalfedgeMesh& mesh, typename HalfedgeMesh::HalfedgeHandle v0v1) {
  if (mesh.status(mesh.edge_handle(v0v1)).deleted()) return false;
  const auto v1v0 = mesh.opposite_halfedge_handle(v0v1);
  const auto v0 = mesh.to_vertex_handle(v1v0), v1 = mesh.to_vertex_handle(v0v1);
  if (mesh.status(v0).deleted() || mesh.status(v1).deleted()) return false;

  // The apex of the triangle on one side of the edge (left unset, invalid, on a boundary side). False when that
  // triangle's two other edges are both boundary edges: the collapse would leave it as a dangling edge.
  const auto apex = [&mesh](typename HalfedgeMesh::HalfedgeHandle side, typename HalfedgeMesh::VertexHandle& apex_vertex) {
    if (mesh.is_boundary(side)) return true;
    const auto h1 = mesh.next_halfedge_handle(side), h2 = mesh.next_halfedge_handle(h1);
    apex_vertex = mesh.to_vertex_handle(h1);
    return !(mesh.is_boundary(mesh.opposite_halfedge_handle(h1)) && mesh.is_boundary(mesh.opposite_halfedge_handle(h2)));
  };
  typename HalfedgeMesh::VertexHandle vl, vr;
  if (!apex(v0v1, vl) || !apex(v1v0, vr)) return false;
  if (vl == vr) return false;  // one apex shared by both sides, or no triangle on either

  // The link condition proper: a neighbour of both ends other than the apexes would be pinched to an edge.
  for (const auto w : mesh.vv_range(v0)) {
    if (w == vl || w == vr) continue;
    for (const auto u : mesh.vv_range(v1))
      if (u == w) return false;
  }
  // An interior edge between two boundary vertices: collapsing it would pinch the surface at the merged vertex.
  return !(mesh.is_boundary(v0) && mesh.is_boundary(v1) && !mesh.is_boundary(v0v1) && !mesh.is_boundary(v1v0));
}

}  // namespace wish::volume
