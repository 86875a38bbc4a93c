// collapse_keeps_manifold (core/volume/link_condition.hpp) gives OpenMesh's own answer (TriConnectivity::
// is_collapse_ok) on every halfedge of a mesh, deleted ones included, before each collapse of a long sequence of
// random legal collapses: on a closed mesh down to a tetrahedron, and on a mesh with a boundary (whose rules only
// that case reaches), until no collapse is legal. Both answers, true and false, must occur, so neither branch goes untested.
#include <cstdio>
#include <random>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <gtest/gtest.h>

#include "core/volume/link_condition.hpp"
#include "tests/testing/test_data.hpp"

namespace wish::volume {
namespace {

struct StatusTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status);
};
using HalfedgeMesh = OpenMesh::TriMesh_ArrayKernelT<StatusTraits>;

HalfedgeMesh to_halfedge_mesh(const Mesh& mesh) {
  HalfedgeMesh m;
  std::vector<HalfedgeMesh::VertexHandle> v;
  for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i)
    v.push_back(m.add_vertex(HalfedgeMesh::Point(mesh.vertices(i, 0), mesh.vertices(i, 1), mesh.vertices(i, 2))));
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) m.add_face(v[mesh.faces(f, 0)], v[mesh.faces(f, 1)], v[mesh.faces(f, 2)]);
  return m;
}

// An n × n grid of squares, each split into two triangles: a disc with a boundary.
Mesh grid_disc(int n) {
  Mesh m;
  m.vertices.resize((n + 1) * (n + 1), 3);
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.vertices.row(y * (n + 1) + x) << x, y, 0;
  m.faces.resize(2 * n * n, 3);
  int f = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      m.faces.row(f++) << a, b, d;
      m.faces.row(f++) << a, d, c;
    }
  return m;
}

struct Agreement {
  long checked = 0, legal = 0, illegal = 0, disagreements = 0, collapses = 0;
};

// Compares the two answers on every halfedge, then collapses one legal halfedge picked at random; until none is left
// or `min_vertices` remain (a tetrahedron passes the vertex link test: the decimater's own valence check stops there).
Agreement compare_through_collapses(HalfedgeMesh m, unsigned seed, long min_vertices) {
  Agreement a;
  std::mt19937 random(seed);
  const long vertices = static_cast<long>(m.n_vertices());
  for (;;) {
    std::vector<HalfedgeMesh::HalfedgeHandle> legal;
    for (int i = 0; i < static_cast<int>(m.n_halfedges()); ++i) {
      const HalfedgeMesh::HalfedgeHandle h(i);
      const bool ours = collapse_keeps_manifold(m, h);
      const bool openmesh = m.is_collapse_ok(h);
      ++a.checked;
      a.disagreements += ours != openmesh;
      if (openmesh) legal.push_back(h);
      (openmesh ? a.legal : a.illegal) += 1;
    }
    if (legal.empty() || vertices - a.collapses <= min_vertices) return a;
    m.collapse(legal[std::uniform_int_distribution<std::size_t>(0, legal.size() - 1)(random)]);
    ++a.collapses;
  }
}

TEST(LinkCondition, AgreesWithOpenMeshThroughAClosedMeshsCollapseToATetrahedron) {
  const Mesh sphere = testing::make_ellipsoid(1.0, 0.8, 0.6, 2);  // 162 vertices
  const Agreement a = compare_through_collapses(to_halfedge_mesh(sphere), 7, 4);
  std::printf("closed: %ld answers compared (%ld legal, %ld not) over %ld collapses\n", a.checked, a.legal, a.illegal,
              a.collapses);
  EXPECT_EQ(a.disagreements, 0);
  EXPECT_EQ(a.collapses, sphere.vertex_count() - 4);  // a legal collapse exists down to a tetrahedron
  EXPECT_GT(a.legal, 0);
  EXPECT_GT(a.illegal, 0);
}

TEST(LinkCondition, AgreesWithOpenMeshThroughADiscsCollapses) {
  for (const unsigned seed : {1u, 2u, 3u}) {
    const Agreement a = compare_through_collapses(to_halfedge_mesh(grid_disc(6)), seed, 3);
    std::printf("disc (seed %u): %ld answers compared (%ld legal, %ld not) over %ld collapses\n", seed, a.checked,
                a.legal, a.illegal, a.collapses);
    EXPECT_EQ(a.disagreements, 0);
    EXPECT_GT(a.collapses, 30);
    EXPECT_GT(a.illegal, 0);
  }
}

}  // namespace
}  // namespace wish::volume
