// Map acceptance and time over mesh collections (issue 11): one row per directory and one for all of them.
//   map_collection_bench DIR|LIST.txt|MESH [...]   (DIR: recursive, .off .obj .ply .stl; LIST.txt: one path a line)
// Per mesh: read → prepare_for_mapping → compute_spherical_map with the default options (--method M: the chain
// that starts with M, as a model whose recipe has that method and the default off-recipe policy, refuse, runs it:
// prefer_method; --no-needle-aware: the chain without its needle retry and needle-aware choice, as before issue 24 item 3,
// map_chain.cpp). Columns: meshes found,
// accepted by validation (closed genus-0 manifold), 0-flip rate and Ok rate of the accepted, map time median / p95
// / max (wall-clock seconds, one core: run with OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1) and the same in CPU
// seconds of the mapping thread (what the flow budget counts; load-independent), the method each map ended on, the
// verdicts, and the K p99 and area distortion (exp mean |log area ratio|, map_verification.hpp) distributions
// (median / p90 / max over bijective maps). Refusal codes are counted below.
// A second table (the time bound of issue 11: the final answer within 3 CPU s per 10K vertices, scaled with
// max(1, V/10K)): CPU s per 10K vertices median / p95 / max, meshes over 3 s per 10K, CPU median / max by the method
// each map ended on, and how many maps a budget stopped (an attempt with stop time_budget, a repair the chain budget
// stopped, or a skipped attempt).
// Per mesh (stderr): the chain as run, method/stop:flips+degenerate K p99|K p99 of the well-shaped faces/CPU seconds
// per attempt, then skipped ones.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/common/cpu_budget.hpp"
#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"

namespace {

struct Row {
  std::string name;
  int found = 0, accepted = 0, zero_flips = 0, ok = 0;
  std::vector<double> seconds, cpu_seconds, k_p99, area_distortion;
  std::vector<double> cpu_per_10k;                        // CPU s / max(1, V/10K)
  std::map<std::string, std::vector<double>> method_cpu;  // CPU s by the method the map ended on
  int budget_stops = 0;                                    // maps where the flow budget stopped or skipped an attempt
  std::map<std::string, int> methods, verdicts, refusals;
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

std::string counts(const std::map<std::string, int>& m) {
  std::string s;
  for (const auto& [k, n] : m) s += (s.empty() ? "" : " ") + k + ":" + std::to_string(n);
  return s.empty() ? "-" : s;
}

double step_seconds(const wish::MapAttempt& a) {
  double s = 0;
  for (const wish::FlowStepRecord& r : a.steps) s += r.seconds;
  return s;
}

void map_one(const std::filesystem::path& path, const wish::SphericalMapOptions& options, Row& row, Row& all) {
  ++row.found;
  ++all.found;
  wish::PreparedMesh prepared;
  try {
    prepared = wish::prepare_for_mapping(wish::read_mesh_file(path).mesh);
  } catch (const wish::WishError& e) {
    ++row.refusals[e.code()];
    ++all.refusals[e.code()];
    return;
  }
  if (!prepared.mappable()) {
    ++row.refusals[prepared.issues.front().code];
    ++all.refusals[prepared.issues.front().code];
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = wish::CpuBudget::thread_cpu_seconds();
  const wish::SphericalMapResult r = wish::compute_spherical_map(prepared.mesh, options);
  const double cpu = wish::CpuBudget::thread_cpu_seconds() - cpu0;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (Row* x : {&row, &all}) {
    ++x->accepted;
    x->seconds.push_back(s);
    x->cpu_seconds.push_back(cpu);
    const bool bijective = r.quality.flipped_faces == 0 && r.quality.degenerate_faces == 0 && r.quality.degree == 1 &&
                           r.quality.non_finite_vertices == 0;
    x->zero_flips += r.quality.flipped_faces == 0;
    x->ok += r.ok();
    if (bijective) x->k_p99.push_back(r.quality.conformal_p99);
    if (bijective) x->area_distortion.push_back(r.quality.area_distortion);
    x->cpu_per_10k.push_back(cpu / std::max(1.0, static_cast<double>(prepared.mesh.vertex_count()) / 1e4));
    x->method_cpu[wish::to_string(r.method_used)].push_back(cpu);
    bool budget_stop = !r.skipped_for_budget.empty();
    for (const wish::MapAttempt& a : r.attempts)
      budget_stop = budget_stop || a.stop == wish::FlowStop::TimeBudget || a.repair_budget_stopped;
    x->budget_stops += budget_stop;
    ++x->methods[wish::to_string(r.method_used)];
    ++x->verdicts[wish::to_string(r.verdict)];
  }
  // The chain as run: method/stop:flips+degenerate faces/seconds per attempt.
  std::string chain;
  for (const wish::MapAttempt& a : r.attempts)
    chain += std::string(chain.empty() ? "" : " > ") + wish::to_string(a.method) + (a.needle ? "(needle)" : "") + "/" + wish::to_string(a.stop) + ":" +
             std::to_string(a.quality.flipped_faces) + "+" + std::to_string(a.quality.degenerate_faces) + " K" +
             std::to_string(a.quality.conformal_p99).substr(0, 5) + "|" +
             std::to_string(a.quality.conformal_p99_well_shaped).substr(0, 5) + "/" +
             std::to_string(a.cpu_seconds).substr(0, 4) + "s" +
             (a.quality.repaired_vertices > 0 ? " (repaired " + std::to_string(a.quality.repaired_vertices) + ")" : "") +
             (a.repair_cpu_seconds >= 0.05 ? " repair " + std::to_string(a.repair_cpu_seconds).substr(0, 4) + "s" : "") +
             (a.repair_budget_stopped ? " (repair stopped: chain budget)" : "") +
             (std::getenv("WISH_BENCH_STEPS") ? " steps " + std::to_string(a.steps.size()) + " in " +
                                                    std::to_string(step_seconds(a)).substr(0, 4) + "s wall"
                                              : "");
  for (const wish::MapAttemptPlan& p : r.skipped_for_budget)
    chain += std::string(" > (") + wish::to_string(p.method) + " skipped: time_budget)";
  std::fprintf(stderr, "%-60s V=%7ld %-8s %-9s flips %ld degen %ld K p99 %.2f %.2fs cpu %.2fs  [%s]\n",
               path.string().c_str(), static_cast<long>(prepared.mesh.vertex_count()), wish::to_string(r.method_used),
               wish::to_string(r.verdict), r.quality.flipped_faces, r.quality.degenerate_faces,
               r.quality.conformal_p99, s, cpu, chain.c_str());
}

void print_time_bound(const Row& r) {
  const double bound = 3.0;  // CPU s per 10K vertices (issue 11)
  int over = 0;
  for (double c : r.cpu_per_10k) over += c > bound;
  std::string by_method;
  for (const auto& [m, v] : r.method_cpu) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s%s %.2f/%.2f", by_method.empty() ? "" : ", ", m.c_str(), quantile(v, 0.5),
                  *std::max_element(v.begin(), v.end()));
    by_method += buf;
  }
  std::printf("| %-28s | %5d | %5.2f / %5.2f / %6.2f | %4d | %-50s | %4d |\n", r.name.c_str(), r.accepted,
              quantile(r.cpu_per_10k, 0.5), quantile(r.cpu_per_10k, 0.95),
              r.cpu_per_10k.empty() ? 0.0 : *std::max_element(r.cpu_per_10k.begin(), r.cpu_per_10k.end()), over,
              by_method.c_str(), r.budget_stops);
}

void print(const Row& r) {
  const double n = std::max(1, r.accepted);
  const auto max_of = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
  std::printf("| %-28s | %5d | %5d | %6.1f %% | %6.1f %% | %5.2f / %5.2f / %6.2f | %5.2f / %5.2f / %6.2f | %-30s | %-36s "
              "| %6.2f / %6.2f / %8.2f | %6.2f / %6.2f / %8.2f |\n",
              r.name.c_str(), r.found, r.accepted, 100.0 * r.zero_flips / n, 100.0 * r.ok / n, quantile(r.seconds, 0.5),
              quantile(r.seconds, 0.95), max_of(r.seconds), quantile(r.cpu_seconds, 0.5), quantile(r.cpu_seconds, 0.95),
              max_of(r.cpu_seconds),
              counts(r.methods).c_str(), counts(r.verdicts).c_str(), quantile(r.k_p99, 0.5), quantile(r.k_p99, 0.9),
              r.k_p99.empty() ? 0.0 : *std::max_element(r.k_p99.begin(), r.k_p99.end()), quantile(r.area_distortion, 0.5),
              quantile(r.area_distortion, 0.9), max_of(r.area_distortion));
}

}  // namespace

int main(int argc, char** argv) {
  const auto usage = [&] {
    std::fprintf(stderr,
                 "usage: %s [--method willmore|cmcf|linear] [--no-needle-aware] DIR|LIST.txt|MESH [...]  (DIR recursive: .off .obj .ply "
                 ".stl; LIST.txt one path a line)\n",
                 argv[0]);
    return 2;
  };
  wish::SphericalMapOptions options;
  std::vector<std::string> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") return usage() - 2;
    if (a == "--method" && i + 1 < argc) {  // the chain of a model with this recipe method and the refuse policy
      options.method = wish::map_method_from_name(argv[++i]);
      options.prefer_method = true;
      continue;
    }
    if (a == "--no-needle-aware") {  // the chain without its needle retry and choice (A/B of issue 24 item 3)
      options.needle_aware = false;
      continue;
    }
    if (!std::filesystem::exists(a)) {
      std::fprintf(stderr, "%s: no such file or directory: %s\n", argv[0], a.c_str());
      return usage();
    }
    inputs.push_back(a);
  }
  if (inputs.empty()) return usage();
  std::vector<Row> rows;
  Row all;
  all.name = "all";
  for (const std::string& input : inputs) {
    Row row;
    row.name = std::filesystem::path(input).filename().string();
    if (row.name.empty()) row.name = input;
    std::vector<std::filesystem::path> files;
    if (std::filesystem::path(input).extension() == ".txt") {  // a list of mesh paths, one a line
      std::ifstream list(input);
      for (std::string line; std::getline(list, line);)
        if (!line.empty()) files.push_back(line);
      row.name = std::filesystem::path(input).stem().string();
    } else if (std::filesystem::is_regular_file(input)) {
      files.push_back(input);  // one mesh: its own row
    } else
      for (const auto& e : std::filesystem::recursive_directory_iterator(input)) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file() && (ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl")) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) map_one(f, options, row, all);
    rows.push_back(std::move(row));
  }
  std::printf("| collection | found | accepted | 0-flip | ok | map s median / p95 / max | map CPU s median / p95 / max | methods | verdicts | K p99 median / p90 / max | area distortion median / p90 / max |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) print(r);
  if (rows.size() > 1) print(all);
  std::printf("\n| collection | mapped | CPU s per 10K V median / p95 / max | over 3 s/10K | CPU s median/max by method ended on | budget stops |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const Row& r : rows) print_time_bound(r);
  if (rows.size() > 1) print_time_bound(all);
  std::printf("\nrefused by validation or reading: %s\n", counts(all.refusals).c_str());
  return 0;
}
