// Path- and resolution-independence of the descriptor (issue 37): each mesh is mapped from several starts (each map
// method alone, no fallback), relaxed to the canonical map, fitted, and its log ξ(1..Lmax) compared across the starts;
// with --subdivide N also against the same surface subdivided N times (identical geometry, 4^N times the faces).
//   canonical_map_bench FILE... [--starts cmcf,willmore,linear,progressive] [--canonical isometric|none]
//                       [--mean-damping] [--no-extrapolate] [--max-iterations N] [--budget S]
//                       [--lmax 10] [--nu 1e-1] [--sampling vertices|surface] [--subdivide N]
// Prints one row per mesh and start: the start's method and status, the relaxation's steps, stop, energy and CPU
// seconds, and max_l |Δ log ξ(l)| against the first start that mapped (and against the original resolution).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/mesh/subdivision.hpp"
#include "core/sh/sh_fit.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"

namespace {

using namespace wish;

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

const char* stop_name(CanonicalMapStop s) {
  switch (s) {
    case CanonicalMapStop::NotRun: return "not_run";
    case CanonicalMapStop::Converged: return "converged";
    case CanonicalMapStop::IterationCap: return "iteration_cap";
    case CanonicalMapStop::TimeBudget: return "time_budget";
    case CanonicalMapStop::LineSearchFailed: return "line_search_failed";
    case CanonicalMapStop::SolverFailed: return "solver_failed";
    case CanonicalMapStop::Reverted: return "reverted";
  }
  return "?";
}

struct Described {
  bool ok = false;
  Eigen::VectorXd log_xi;
};

Described describe(const Mesh& mesh, MapMethod method, const SphericalMapOptions& base, const ShFitOptions& fit,
                   const std::string& label) {
  SphericalMapOptions options = base;
  options.method = method;
  options.fallback = false;
  const double cpu0 = CpuBudget::thread_cpu_seconds();
  const SphericalMapResult map = compute_spherical_map(mesh, options);
  const double map_cpu = CpuBudget::thread_cpu_seconds() - cpu0;
  Described d;
  std::printf("%-28s %-12s %-8s", label.c_str(), to_string(method), map.ok() ? "ok" : to_string(map.failed_check));
  if (!map.ok()) {
    std::printf("\n");
    return d;
  }
  const ShDescriptor sh = fit_spherical_harmonics(mesh, map.sphere, fit);
  d.ok = true;
  d.log_xi = sh.invariants.tail(fit.lmax).array().log();
  const CanonicalMapReport& c = map.canonical;
  std::printf(" steps %3d (+%3d) halvings %3d %-18s E %9.4f -> %9.4f  canon %6.3f s  map %6.3f s  areaD %7.3f Kp99 %7.3f",
              c.iterations, c.extrapolations, c.halvings, stop_name(c.stop), c.energy_start, c.energy, c.seconds, map_cpu,
              map.quality.area_distortion, map.quality.conformal_p99);
  if (map.area_correction.method != AreaCorrection::None)
    std::printf("  dem %d steps, areaD %.3f -> %.3f, %.2f s%s", map.area_correction.iterations,
                map.area_correction.before.area_distortion, map.area_correction.after.area_distortion,
                map.area_correction.seconds, map.area_correction.converged ? "" : " (not converged)");
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  std::vector<std::string> starts{"cmcf", "willmore", "linear", "progressive"};
  std::string canonical = "isometric";
  std::string area_correction = "none";
  bool mean_damping = false, no_extrapolate = false;
  int max_iterations = 0;
  double budget = -1;
  ShFitOptions fit;
  fit.lmax = 10;
  fit.regularization = 1e-1;
  int subdivide = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&] { return std::string(argv[++i]); };
    if (a == "--starts") starts = split(next());
    else if (a == "--canonical") canonical = next();
    else if (a == "--area-correction") area_correction = next();
    else if (a == "--mean-damping") mean_damping = true;
    else if (a == "--no-extrapolate") no_extrapolate = true;
    else if (a == "--max-iterations") max_iterations = std::stoi(next());
    else if (a == "--budget") budget = std::stod(next());
    else if (a == "--lmax") fit.lmax = std::stoi(next());
    else if (a == "--nu") fit.regularization = std::stod(next());
    else if (a == "--subdivide") subdivide = std::stoi(next());
    else if (a == "--sampling") fit.sampling = fit_sampling_from_name(next());
    else files.push_back(a);
  }
  SphericalMapOptions base;
  base.canonical.method = canonical == "none" ? CanonicalMap::None : CanonicalMap::Isometric;
  base.canonical.scaled_damping = !mean_damping;
  base.canonical.extrapolate = !no_extrapolate;
  if (max_iterations > 0) base.canonical.max_iterations = max_iterations;
  if (budget >= 0) base.canonical.budget_seconds = budget;
  base.area_correction.method = area_correction_from_name(area_correction);
  for (const std::string& file : files) {
    try {
      PreparedMesh prepared = prepare_for_mapping(read_mesh_file(file).mesh);
      require_mappable(prepared);
      const Mesh& mesh = prepared.mesh;
      const std::string name = std::filesystem::path(file).filename().string();
      std::vector<Described> rows;
      for (const std::string& s : starts) {
        rows.push_back(describe(mesh, map_method_from_name(s), base, fit, name + " V" + std::to_string(mesh.vertex_count())));
        if (rows.size() > 1 && rows.front().ok && rows.back().ok)
          std::printf("  dlogxi %.4f", (rows.back().log_xi - rows.front().log_xi).cwiseAbs().maxCoeff());
        std::printf("\n");
      }
      if (subdivide > 0) {
        const Mesh fine = subdivide_midpoint(mesh, subdivide);
        const Described d = describe(fine, map_method_from_name(starts.front()), base, fit,
                                     name + " V" + std::to_string(fine.vertex_count()));
        if (d.ok && rows.front().ok)
          std::printf("  dlogxi(sub%d) %.4f", subdivide, (d.log_xi - rows.front().log_xi).cwiseAbs().maxCoeff());
        std::printf("\n");
      }
    } catch (const std::exception& e) {
      std::printf("%s: %s\n", file.c_str(), e.what());
    }
  }
  return 0;
}
