#pragma once
// Where test meshes live, for every test binary:
//  * project_data_dir(): data/ in this repository (small, licence-compatible meshes that are always there);
//  * shared_data_dir(): ../shared/data beside the checkout (override: WISH_SHARED_DATA); may be absent, and a
//    test that needs it calls WISH_SKIP_WITHOUT_SHARED_DATA() to be skipped, not failed.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/mesh/mesh.hpp"

namespace wish::testing {

std::filesystem::path project_data_dir();
std::optional<std::filesystem::path> shared_data_dir();
// Sorted list of regular files in `dir` whose extension is one of `extensions` (e.g. {".off", ".obj"}).
std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir, const std::vector<std::string>& extensions);

// The seed printed on failure; WISH_TEST_SEED overrides the default.
unsigned test_seed(unsigned default_seed = 12345);

// Axis-aligned ellipsoid with semi-axes (a, b, c): an icosphere of `level` scaled per axis.
Mesh make_ellipsoid(double a, double b, double c, int level);
// Random rotation matrix (uniform on SO(3)) from `seed`.
Eigen::Matrix3d random_rotation(unsigned seed);

}  // namespace wish::testing

#define WISH_SKIP_WITHOUT_SHARED_DATA()                                                   \
  do {                                                                                    \
    if (!::wish::testing::shared_data_dir()) GTEST_SKIP() << "../shared/data is absent"; \
  } while (0)
