#include "tests/testing/test_data.hpp"

#include <algorithm>
#include <cstdlib>
#include <random>

#include <Eigen/Geometry>

#include "core/mesh/icosphere.hpp"

namespace wish::testing {

std::filesystem::path project_data_dir() {
  if (const char* env = std::getenv("WISH_PROJECT_DATA")) return env;
  return WISH_PROJECT_DATA_DEFAULT;
}

std::optional<std::filesystem::path> shared_data_dir() {
  std::filesystem::path dir = WISH_SHARED_DATA_DEFAULT;
  if (const char* env = std::getenv("WISH_SHARED_DATA")) dir = env;
  std::error_code ec;
  if (std::filesystem::is_directory(dir / "cgal", ec)) return dir;
  return std::nullopt;
}

std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir, const std::vector<std::string>& extensions) {
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file()) continue;
    const auto ext = entry.path().extension().string();
    if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

unsigned test_seed(unsigned default_seed) {
  if (const char* env = std::getenv("WISH_TEST_SEED")) return static_cast<unsigned>(std::strtoul(env, nullptr, 10));
  return default_seed;
}

Mesh make_ellipsoid(double a, double b, double c, int level) {
  Mesh mesh = make_icosphere(level);
  mesh.vertices.col(0) *= a;
  mesh.vertices.col(1) *= b;
  mesh.vertices.col(2) *= c;
  return mesh;
}

Eigen::Matrix3d random_rotation(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

}  // namespace wish::testing
