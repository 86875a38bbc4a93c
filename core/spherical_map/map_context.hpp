#pragma once
// What every attempt of the map chain shares, built once per mesh (map_chain.hpp runs up to five attempts on one
// mesh; before, each Willmore attempt rebuilt the vertex pattern and its METIS ordering, and each linear attempt
// its operator):
//  * the mesh, checked against the stage's preconditions (closed, manifold, one component, genus 0, outward, no
//    face repeating a vertex; prepare_for_mapping() establishes them) — the constructor throws otherwise;
//  * the vertex pattern (vertex_pattern.hpp) and, for CHOLMOD, the METIS ordering of the vertex graph;
//  * the lumped vertex areas of the input (the Möbius balancing's weights);
//  * the input normalised to area 4π about its area-weighted centroid (where the flows start);
//  * the robust operator (intrinsic_laplacian.hpp) of the input as given (the linear map's) and of the normalised
//    input (cMCF's frozen stiffness L₀).
// The ordering and the operators are computed on first use (a chain that ends on its first attempt never needs
// the others), so a context is not copied and is used by one thread.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/geometry/vertex_pattern.hpp"
#include "core/linalg/sparse_cholesky.hpp"
#include "core/mesh/mesh.hpp"
#include "core/spherical_map/map_types.hpp"

namespace wish::spherical {

class MapContext {
 public:
  // Throws InvalidInputError / WishError(Unmappable) for a mesh that violates the preconditions. `mesh` must
  // outlive the context.
  explicit MapContext(const Mesh& mesh, LinearSolverKind solver = LinearSolverKind::Cholmod,
                      const geometry::IntrinsicOptions& laplacian = {});
  MapContext(const MapContext&) = delete;
  MapContext& operator=(const MapContext&) = delete;

  const Mesh& mesh() const { return mesh_; }
  const Eigen::MatrixX3i& faces() const { return mesh_.faces; }
  Eigen::Index vertex_count() const { return mesh_.vertex_count(); }
  LinearSolverKind solver() const { return solver_; }
  const geometry::IntrinsicOptions& laplacian() const { return laplacian_; }

  const geometry::VertexPattern& pattern() const { return pattern_; }
  // METIS fill-reducing ordering of the vertex graph; empty for the Eigen solver (it orders by itself).
  const std::vector<int>& ordering() const;
  const Eigen::VectorXd& input_mass() const { return input_mass_; }
  const Eigen::MatrixX3d& normalised_input() const { return normalised_; }
  const geometry::IntrinsicOperator& input_operator() const;
  const geometry::IntrinsicOperator& normalised_operator() const;

  // Options of a sparse Cholesky with the context's backend; with `ordered`, CHOLMOD gets ordering() expanded to
  // blocks of `block` unknowns per vertex.
  linalg::CholeskyOptions cholesky_options(linalg::CholmodMode mode, bool ordered, int block = 1) const;

 private:
  const Mesh& mesh_;
  LinearSolverKind solver_;
  geometry::IntrinsicOptions laplacian_;
  geometry::VertexPattern pattern_;
  Eigen::VectorXd input_mass_;
  Eigen::MatrixX3d normalised_;
  mutable std::optional<std::vector<int>> ordering_;
  mutable std::optional<geometry::IntrinsicOperator> input_operator_, normalised_operator_;
};

}  // namespace wish::spherical
