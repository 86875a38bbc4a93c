#include "core/spherical_map/map_context.hpp"

#include <string>

#include "core/common/errors.hpp"
#include "core/common/stage_profile.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/spherical_map/flow_result.hpp"

namespace wish::spherical {
namespace {

// What can be checked before the vertex pattern exists (building it needs valid indices).
void check_counts_and_indices(const Mesh& mesh) {
  const Eigen::Index nv = mesh.vertex_count(), nf = mesh.face_count();
  if (nv < 4 || nf < 4)
    throw WishError(ErrorCategory::Unmappable, "too_small", "a closed mesh needs at least 4 vertices and 4 faces (got " +
                                             std::to_string(nv) + " and " + std::to_string(nf) + ")");
  if (!mesh.vertices.allFinite()) throw InvalidInputError("non_finite_vertex", "mesh has NaN/Inf coordinates");
  if (mesh.faces.minCoeff() < 0 || mesh.faces.maxCoeff() >= nv)
    throw InvalidInputError("index_out_of_range", "face index outside [0, #V)");
}

void check_topology_and_orientation(const Mesh& mesh, const geometry::VertexPattern& pattern) {
  const Eigen::Index nv = mesh.vertex_count(), nf = mesh.face_count();
  const long chi = static_cast<long>(nv) - pattern.edge_count + static_cast<long>(nf);
  if (chi != 2 || 3 * nf != 2 * pattern.edge_count)
    throw WishError(ErrorCategory::Unmappable, "genus_nonzero",
                            "mesh is not a closed genus-0 surface (V - E + F = " + std::to_string(chi) +
                                ", 3F = " + std::to_string(3 * nf) + ", 2E = " + std::to_string(2 * pattern.edge_count) +
                                "); run prepare_for_mapping first",
                            {{"euler_characteristic", std::int64_t{chi}}});
  // Zero-area faces are accepted (the operators mollify them, intrinsic_laplacian.hpp); a face that repeats a
  // vertex is a topological defect.
  Eigen::Index repeated = 0;
  for (Eigen::Index f = 0; f < nf; ++f)
    repeated += mesh.faces(f, 0) == mesh.faces(f, 1) || mesh.faces(f, 1) == mesh.faces(f, 2) ||
                mesh.faces(f, 2) == mesh.faces(f, 0);
  if (repeated > 0)
    throw WishError(ErrorCategory::Unmappable, "degenerate_faces", std::to_string(repeated) + " faces repeat a vertex",
                            {{"count", std::int64_t{repeated}}});
  const double volume = geometry::signed_volume(mesh.vertices, mesh.faces);
  if (!(volume > 0))
    throw WishError(ErrorCategory::Unmappable, "inconsistent_orientation",
                            "signed volume " + std::to_string(volume) + " is not positive: faces must be outward (CCW)",
                            {{"signed_volume", volume}});
}

geometry::VertexPattern checked_pattern(const Mesh& mesh) {
  check_counts_and_indices(mesh);
  geometry::VertexPattern pattern = geometry::build_vertex_pattern(mesh.vertex_count(), mesh.faces);
  check_topology_and_orientation(mesh, pattern);
  return pattern;
}

}  // namespace

MapContext::MapContext(const Mesh& mesh, LinearSolverKind solver, const geometry::IntrinsicOptions& laplacian)
    : mesh_(mesh), solver_(solver), laplacian_(laplacian), pattern_(checked_pattern(mesh)) {
  input_mass_ = geometry::lumped_mass(mesh.vertices, mesh.faces);
  normalised_ = mesh.vertices;
  normalise_area_and_centre(normalised_, mesh.faces);
}

const std::vector<int>& MapContext::ordering() const {
  if (!ordering_) {
    const profile::ScopedStage stage("map.context.metis_ordering");
    ordering_ = solver_ == LinearSolverKind::Cholmod ? linalg::metis_ordering(pattern_.pattern) : std::vector<int>{};
  }
  return *ordering_;
}

const geometry::IntrinsicOperator& MapContext::input_operator() const {
  if (!input_operator_) input_operator_ = geometry::intrinsic_operator(mesh_.vertices, mesh_.faces, laplacian_);
  return *input_operator_;
}

const geometry::IntrinsicOperator& MapContext::normalised_operator() const {
  if (!normalised_operator_) normalised_operator_ = geometry::intrinsic_operator(normalised_, mesh_.faces, laplacian_);
  return *normalised_operator_;
}

linalg::CholeskyOptions MapContext::cholesky_options(linalg::CholmodMode mode, bool ordered, int block) const {
  linalg::CholeskyOptions o;
  o.backend = solver_ == LinearSolverKind::Cholmod ? linalg::CholeskyBackend::Cholmod
                                                   : linalg::CholeskyBackend::EigenSimplicial;
  o.cholmod_mode = mode;
  if (ordered && solver_ == LinearSolverKind::Cholmod) {
    const std::vector<int>& perm = ordering();
    o.permutation = block == 1 || perm.empty() ? perm : linalg::expand_ordering(perm, block);
  }
  return o;
}

}  // namespace wish::spherical
