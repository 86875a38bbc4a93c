// The needle retry's exact repair (star_kernel_repair.hpp) and the ordered one-rings it walks
// (ordered_one_rings.hpp): a vertex pushed out of its one-ring goes back into its kernel, only it moves, and the map
// passes the verification's flip and degree checks again; a map without bad faces is left bit for bit.
#include <algorithm>
#include <array>
#include <set>

#include <gtest/gtest.h>

#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/ordered_one_rings.hpp"
#include "core/spherical_map/star_kernel_repair.hpp"

namespace wish::spherical {
namespace {

// The icosphere's own vertices: a bijective sphere map of itself.
Eigen::MatrixX3d unit_vertices(const Mesh& m) { return m.vertices.rowwise().normalized(); }

long bad_faces(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces) {
  return count_bad_sphere_faces(sphere, faces, 1e-14);
}

TEST(OrderedOneRings, EveryConsecutivePairIsAFaceOfTheVertexInItsOrientation) {
  const Mesh m = make_icosphere(2);
  const auto rings = ordered_one_rings(m.faces, m.vertex_count());
  ASSERT_TRUE(rings.has_value());
  std::set<std::array<int, 3>> faces;  // each face in its three rotations
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) faces.insert({m.faces(f, k), m.faces(f, (k + 1) % 3), m.faces(f, (k + 2) % 3)});
  size_t corners = 0;
  for (size_t v = 0; v < rings->size(); ++v) {
    const std::vector<int>& ring = (*rings)[v];
    corners += ring.size();
    for (size_t j = 0; j < ring.size(); ++j)
      EXPECT_TRUE(faces.count({static_cast<int>(v), ring[j], ring[(j + 1) % ring.size()]})) << "vertex " << v;
  }
  EXPECT_EQ(corners, static_cast<size_t>(3 * m.faces.rows()));
}

TEST(OrderedOneRings, AnOpenMeshHasNone) {
  Mesh m = make_icosphere(1);
  const Eigen::MatrixX3i open = m.faces.topRows(m.faces.rows() - 1);
  EXPECT_FALSE(ordered_one_rings(open, m.vertex_count()).has_value());
}

TEST(StarKernelRepair, PutsAVertexPushedAcrossItsLinkBackIntoItsKernelMovingNothingElse) {
  const Mesh m = make_icosphere(3);
  const auto rings = ordered_one_rings(m.faces, m.vertex_count());
  ASSERT_TRUE(rings.has_value());
  Eigen::MatrixX3d sphere = unit_vertices(m);
  const int v = 17;
  const std::vector<int>& ring = (*rings)[static_cast<size_t>(v)];
  // Push v across its link edge (ring[0], ring[1]): past the edge's midpoint by half of v's distance to it.
  const Eigen::Vector3d mid = 0.5 * (sphere.row(ring[0]) + sphere.row(ring[1])).transpose();
  const Eigen::Vector3d u = sphere.row(v).transpose();
  sphere.row(v) = (mid + 0.5 * (mid - u)).normalized().transpose();
  const Eigen::MatrixX3d pushed = sphere;
  ASSERT_GT(bad_faces(sphere, m.faces), 0);  // precondition: the push flips faces of v's star
  const StarKernelRepairResult r = place_in_star_kernels(sphere, m.faces, *rings, MapVerificationThresholds{});
  EXPECT_GT(r.bad_faces_before, 0);
  EXPECT_EQ(r.bad_faces_after, 0);
  EXPECT_EQ(r.moved_vertices, 1);
  for (Eigen::Index i = 0; i < sphere.rows(); ++i) {
    if (i != v) {
      EXPECT_TRUE(sphere.row(i) == pushed.row(i)) << "vertex " << i << " moved";
    }
  }
  EXPECT_NEAR(sphere.row(v).norm(), 1.0, 1e-12);
  const MapQuality q = measure_map(m.vertices, m.faces, sphere, MapVerificationThresholds{});
  EXPECT_EQ(q.flipped_faces, 0);
  EXPECT_EQ(q.degenerate_faces, 0);
  EXPECT_EQ(q.degree, 1);
}

TEST(StarKernelRepair, LeavesAMapWithoutBadFacesAsItIs) {
  const Mesh m = make_icosphere(2);
  const auto rings = ordered_one_rings(m.faces, m.vertex_count());
  ASSERT_TRUE(rings.has_value());
  Eigen::MatrixX3d sphere = unit_vertices(m);
  const Eigen::MatrixX3d before = sphere;
  const StarKernelRepairResult r = place_in_star_kernels(sphere, m.faces, *rings, MapVerificationThresholds{});
  EXPECT_EQ(r.bad_faces_before, 0);
  EXPECT_EQ(r.moves, 0);
  EXPECT_TRUE(sphere == before);
}

TEST(StarKernelRepair, NeverAddsBadFacesWhenAVertexHasNoKernel) {
  // Two vertices swapped: each one's star is tangled around the other, so the repair may not fix it; whatever it
  // does, the number of bad faces must not grow (every move only places a vertex where its whole star is good).
  const Mesh m = make_icosphere(3);
  const auto rings = ordered_one_rings(m.faces, m.vertex_count());
  ASSERT_TRUE(rings.has_value());
  Eigen::MatrixX3d sphere = unit_vertices(m);
  const int a = 40, b = (*rings)[40][0];
  sphere.row(a).swap(sphere.row(b));
  const long before = bad_faces(sphere, m.faces);
  ASSERT_GT(before, 0);
  const StarKernelRepairResult r = place_in_star_kernels(sphere, m.faces, *rings, MapVerificationThresholds{});
  EXPECT_EQ(r.bad_faces_before, before);
  EXPECT_LE(r.bad_faces_after, before);
  EXPECT_EQ(r.bad_faces_after, bad_faces(sphere, m.faces));
}

}  // namespace
}  // namespace wish::spherical
