#include "core/spherical_map/flow_result.hpp"

#include <cmath>
#include <numbers>

#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/roundness.hpp"

namespace wish::spherical {

void normalise_area_and_centre(Eigen::MatrixX3d& x, const Eigen::MatrixX3i& faces) {
  const Eigen::VectorXd mass = geometry::lumped_mass(x, faces);
  const double area = mass.sum();
  const Eigen::Vector3d c = geometry::area_weighted_centroid(x, mass);
  x.rowwise() -= c.transpose();
  x *= std::sqrt(4.0 * std::numbers::pi / area);
}

}  // namespace wish::spherical
