// Area distortion of the progressive embedding (issue 24 item 2: "its area distortion must stay bounded on thin
// parts"), one row per mesh:
//   progressive_area_bench DIR|MESH [...]   (DIR: recursive, .off .obj .ply .stl)
// Per mesh: read → prepare_for_mapping → compute_spherical_map with method progressive and prefer_method (the
// progressive embedding alone, as `wish map --method progressive`), then the per-face area ratio
// r_f = (a_f / Σa) / (A_f / ΣA) (map_verification.hpp face_distortion: sphere chord-triangle area share over input
// area share; 1 = equiareal). Columns: V, status, flipped + degenerate faces, CPU s of the map, min / p1 / median /
// p99 / max of r_f, max r / min r, the verification's area distortion exp(mean |log r_f|), and the attempt's
// message (which spreading was kept, the retries). Zero-area input faces (r_f not finite) are left out.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/common/cpu_budget.hpp"
#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"

namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

void map_one(const std::filesystem::path& path) {
  wish::PreparedMesh prepared;
  try {
    prepared = wish::prepare_for_mapping(wish::read_mesh_file(path).mesh);
  } catch (const wish::WishError& e) {
    std::printf("| %s | refused %s |\n", path.string().c_str(), e.code().c_str());
    return;
  }
  if (!prepared.mappable()) {
    std::printf("| %s | refused %s |\n", path.string().c_str(), prepared.issues.front().code.c_str());
    return;
  }
  wish::SphericalMapOptions options;
  options.method = wish::MapMethod::Progressive;
  options.prefer_method = true;
  const double cpu0 = wish::CpuBudget::thread_cpu_seconds();
  const wish::SphericalMapResult r = wish::compute_spherical_map(prepared.mesh, options);
  const double cpu = wish::CpuBudget::thread_cpu_seconds() - cpu0;
  std::vector<double> ratio;
  if (r.sphere.allFinite()) {
    const auto d = wish::spherical::face_distortion(prepared.mesh.vertices, prepared.mesh.faces, r.sphere);
    for (Eigen::Index f = 0; f < d.area_ratio.size(); ++f)
      if (std::isfinite(d.area_ratio[f]) && d.input_area[f] > 0) ratio.push_back(d.area_ratio[f]);
  }
  const double lo = ratio.empty() ? 0 : *std::min_element(ratio.begin(), ratio.end());
  const double hi = ratio.empty() ? 0 : *std::max_element(ratio.begin(), ratio.end());
  const std::string message = r.attempts.empty() ? "" : r.attempts[static_cast<size_t>(r.chosen_attempt)].message;
  std::printf("| %s | %ld | %s | %ld+%ld | %.2f | %.2e | %.2e | %.2f | %.2e | %.2e | %.2e | %.3g | %s |\n",
              path.string().c_str(), static_cast<long>(prepared.mesh.vertex_count()), wish::to_string(r.status),
              r.quality.flipped_faces, r.quality.degenerate_faces, cpu, lo, quantile(ratio, 0.01), quantile(ratio, 0.5),
              quantile(ratio, 0.99), hi, lo > 0 ? hi / lo : INFINITY, r.quality.area_distortion, message.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]).starts_with("-")) {
    std::fprintf(stderr, "usage: %s DIR|MESH [...]  (DIR recursive: .off .obj .ply .stl)\n", argv[0]);
    return 2;
  }
  std::printf("| mesh | V | status | flips+degen | CPU s | r min | r p1 | r median | r p99 | r max | max/min | area "
              "distortion | message |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int i = 1; i < argc; ++i) {
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_regular_file(argv[i]))
      files.push_back(argv[i]);
    else
      for (const auto& e : std::filesystem::recursive_directory_iterator(argv[i])) {
        const std::string ext = e.path().extension().string();
        if (e.is_regular_file() && (ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl")) files.push_back(e.path());
      }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) map_one(f);
  }
  return 0;
}
