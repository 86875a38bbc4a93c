#include "core/sh/sh_reconstruction.hpp"

#include <cstdint>
#include <string>

#include "core/common/errors.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_conversion.hpp"

namespace wish {

Eigen::MatrixX3d evaluate_sh_surface(const ShDescriptor& descriptor, const Eigen::MatrixX3d& sphere_points) {
  const int lmax = sh_lmax_from_count(descriptor.coefficients.rows());
  const Eigen::MatrixXd real = complex_to_real_coefficients(descriptor.coefficients);
  return ShBasis::get(lmax)->synthesize(sphere_points, real);
}

Mesh reconstruct_on_icosphere(const ShDescriptor& descriptor, int level) {
  if (level < 0 || level > 7)
    throw InvalidInputError("invalid_parameter",
                            "reconstruction level " + std::to_string(level) + " is outside [0, 7]",
                            {{"level", std::int64_t{level}}});
  Mesh sphere = make_icosphere(level);
  return reconstruct_on_mesh(descriptor, sphere.vertices, sphere.faces);
}

Mesh reconstruct_on_mesh(const ShDescriptor& descriptor, const Eigen::MatrixX3d& sphere_points,
                         const Eigen::MatrixX3i& faces) {
  if (faces.size() > 0 && (faces.minCoeff() < 0 || faces.maxCoeff() >= sphere_points.rows()))
    throw InvalidInputError("index_out_of_range", "a face index is outside the sphere points");
  Mesh mesh;
  mesh.vertices = evaluate_sh_surface(descriptor, sphere_points);
  mesh.faces = faces;
  return mesh;
}

}  // namespace wish
