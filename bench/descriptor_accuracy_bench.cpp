// Descriptor accuracy benchmark (issue 12): which descriptor recipe classifies best, measured by nested, repeated
// stratified CV accuracy (training.hpp nested_cross_validation) on labelled datasets given as directories of class
// folders of meshes. Configurations: map method (willmore, cmcf, linear — each with the chain a model of that recipe
// runs, keeping only the maps that method made: every descriptor of a row comes from one method, and a map from a
// fallback of another method counts as off_recipe_<method>, as `wish train` refuses it), SH regularisation nu (the SH
// fit's default 1e-5, i.e. the paper's nu/10^4 at unit-sum weights, against x10^2 and x10^4 stronger), Lmax, scale
// normalisation xi(l)/xi(1) on/off, log on/off, and feature family xi alone / global alone / combined (xi + global).
// Each map is computed once per mesh and method and reused for every fit setting; each fit once per (nu, Lmax)
// and reused for every feature setting. A row's meshes are those its method mapped (n in the table); global
// alone is measured on the same meshes, so every row compares xi with global on paired data.
//   descriptor_accuracy_bench --data DIR [--data DIR ...] [--methods willmore,cmcf,linear] [--nu 1,100,10000]
//     [--lmax 10,15,25] [--max-per-class N] [--jobs J] [--repeats R] [--folds F] [--c-range A B]
//     [--gamma-range A B] [--max-k-p99 X] [--map-seconds S] [--csv OUT.csv] [--paired]
// --flow-budget S: the flows' soft time budget (SphericalMapOptions::flow_budget_seconds, CPU seconds of the mapping
// thread per 10,000 vertices; default 2): a generous budget lets every flow run to convergence, so a row's mapped
// share measures the method rather than the budget.
// --chain-budget S: the whole chain's CPU budget (SphericalMapOptions::chain_budget_seconds, per 10,000 vertices,
// default 3; 0 = none). A --flow-budget above it is capped by it (less the linear reserve): raise both.
// --paired: every row uses only the meshes that every listed method mapped (the same meshes for every method, so
// rows compare methods on paired data; without it a row has the meshes its own method mapped).
// --area-correction none,dem: map variants per method (density_equalizing.hpp): "none" is the conformal map,
// "dem" the density-equalising correction of the SAME conformal map (rows "cmcf+dem", ...; its CPU seconds and
// area distortion before/after are summarised per row). Default: none.
// --log off|on|both, --scale none|xi1|both: restrict the feature grid (default both, both).
// --dump-descriptors OUT.csv: also write every mapped mesh's raw descriptor (one row per mesh, method, nu and Lmax:
// xi(0..Lmax) before the feature pipeline, then the global descriptors), to study feature variants offline.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <omp.h>

#include "core/classify/feature_pipeline.hpp"
#include "core/classify/global_descriptors.hpp"
#include "core/common/deadline.hpp"
#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/linalg/blas_info.hpp"
#include "core/sh/sh_fit.hpp"
#include "core/spherical_map/density_equalizing.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/training/grid_search.hpp"
#include "core/training/training.hpp"
#include "core/validation/mesh_report.hpp"

namespace fs = std::filesystem;
using namespace wish;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

bool is_mesh_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

struct Item {
  std::string file, label;
};

// Class folders of meshes; at most `per_class` per class, evenly spaced over the sorted file list (deterministic).
std::vector<Item> list_dataset(const fs::path& root, int per_class, std::map<std::string, int>& available) {
  std::vector<fs::path> dirs;
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_directory()) dirs.push_back(e.path());
  std::sort(dirs.begin(), dirs.end());
  std::vector<Item> items;
  for (const auto& d : dirs) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(d))
      if (e.is_regular_file() && is_mesh_file(e.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) continue;
    available[d.filename().string()] = static_cast<int>(files.size());
    const std::size_t n = per_class > 0 ? std::min<std::size_t>(files.size(), static_cast<std::size_t>(per_class)) : files.size();
    for (std::size_t i = 0; i < n; ++i)
      items.push_back({files[i * files.size() / n].string(), d.filename().string()});
  }
  return items;
}

struct MethodOutcome {
  bool ok = false;
  std::string failure;  // error code / failed check
  double seconds = 0;
  AreaCorrectionReport correction;  // variants with an area correction
  std::vector<Eigen::VectorXd> xi;  // per (nu index, lmax index): nu-major
};

struct MeshRecord {
  std::string file, label;
  std::string refused;  // validation / read error code; empty when the mesh is usable
  Eigen::VectorXd global;
  std::vector<MethodOutcome> methods;
};

struct Config {
  std::string method;
  double nu_factor = 1;
  int lmax = 0;
  bool scale = false, log = false;
};

struct Score {
  double mean = 0, std = 0;
  int folds = 0;
};

Score score_of(const NestedCvResult& r) { return {r.mean, r.std, static_cast<int>(r.scores.size())}; }

std::string pct(const Score& s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%5.1f±%4.1f", 100 * s.mean, 100 * s.std);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> data_dirs;
  std::vector<std::string> methods{"willmore", "cmcf", "linear"};
  std::vector<double> nu_factors{1, 100, 10000};
  std::vector<int> lmaxes{10, 15, 25};
  int per_class = 0, jobs = 2, repeats = 2, folds = 5;
  int c_range[2] = {-1, 5}, gamma_range[2] = {-5, 1};
  double max_k_p99 = SphericalMapOptions{}.verification.max_conformal_p99, map_seconds = 120;
  std::string csv_out, dump_out;
  bool paired = false;
  double flow_budget = SphericalMapOptions{}.flow_budget_seconds;
  double chain_budget = SphericalMapOptions{}.chain_budget_seconds;
  std::vector<std::string> corrections{"none"};
  std::vector<bool> log_options{false, true}, scale_options{false, true};
  auto on_off = [](const std::string& v, const char* off, const char* on) {
    if (v == off) return std::vector<bool>{false};
    if (v == on) return std::vector<bool>{true};
    if (v == "both") return std::vector<bool>{false, true};
    std::cerr << "expected " << off << " | " << on << " | both, got " << v << "\n";
    std::exit(2);
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--data") data_dirs.push_back(next());
    else if (a == "--methods") methods = split_list(next());
    else if (a == "--nu") {
      nu_factors.clear();
      for (const auto& v : split_list(next())) nu_factors.push_back(std::stod(v));
    } else if (a == "--lmax") {
      lmaxes.clear();
      for (const auto& v : split_list(next())) lmaxes.push_back(std::stoi(v));
    } else if (a == "--max-per-class") per_class = std::stoi(next());
    else if (a == "--jobs") jobs = std::stoi(next());
    else if (a == "--repeats") repeats = std::stoi(next());
    else if (a == "--folds") folds = std::stoi(next());
    else if (a == "--c-range") {
      c_range[0] = std::stoi(next());
      c_range[1] = std::stoi(next());
    } else if (a == "--gamma-range") {
      gamma_range[0] = std::stoi(next());
      gamma_range[1] = std::stoi(next());
    } else if (a == "--max-k-p99") max_k_p99 = std::stod(next());
    else if (a == "--map-seconds") map_seconds = std::stod(next());
    else if (a == "--csv") csv_out = next();
    else if (a == "--dump-descriptors") dump_out = next();
    else if (a == "--paired") paired = true;
    else if (a == "--flow-budget") flow_budget = std::stod(next());
    else if (a == "--chain-budget") chain_budget = std::stod(next());
    else if (a == "--area-correction") corrections = split_list(next());
    else if (a == "--log") log_options = on_off(next(), "off", "on");
    else if (a == "--scale") scale_options = on_off(next(), "none", "xi1");
    else {
      std::cerr << "unknown argument " << a << "\n";
      return 2;
    }
  }
  if (data_dirs.empty()) {
    std::cerr << "usage: descriptor_accuracy_bench --data DIR [--data DIR ...] (class folders of meshes)\n";
    return 2;
  }
  // Columns: every (method, area correction); the corrected variants start from the same conformal map.
  std::vector<MapMethod> method_enums;
  std::vector<AreaCorrection> correction_enums;
  {
    std::vector<std::string> names;
    for (const auto& m : methods)
      for (const auto& c : corrections) {
        method_enums.push_back(map_method_from_name(m));
        correction_enums.push_back(area_correction_from_name(c));
        names.push_back(correction_enums.back() == AreaCorrection::None ? m : m + "+dem");
      }
    methods = names;
  }
  const int lmax_top = *std::max_element(lmaxes.begin(), lmaxes.end());
  (void)linalg::set_blas_threads(1);

  std::ofstream csv;
  if (!csv_out.empty()) {
    csv.open(csv_out);
    csv << "dataset,method,n,nu_factor,lmax,scale,log,family,accuracy_mean,accuracy_std,folds\n";
  }

  std::ofstream dump;
  if (!dump_out.empty()) {
    dump.open(dump_out);
    dump.precision(17);
    dump << "dataset,method,file,label,nu_factor,lmax";
    for (int l = 0; l <= lmax_top; ++l) dump << ",xi_" << l;
    for (const auto& g : global_descriptor_names()) dump << ",g_" << g;
    dump << "\n";
  }

  for (const auto& dir : data_dirs) {
    const std::string dataset = fs::path(dir).filename().string().empty() ? dir : fs::path(dir).filename().string();
    std::map<std::string, int> available;
    const std::vector<Item> items = list_dataset(dir, per_class, available);
    std::printf("\n=== dataset %s (%s): %zu meshes used", dataset.c_str(), dir.c_str(), items.size());
    for (const auto& [label, n] : available) std::printf(", %s %d", label.c_str(), n);
    std::printf(" available%s\n", per_class > 0 ? (", at most " + std::to_string(per_class) + " per class").c_str() : "");
    std::fflush(stdout);

    // ---- maps (once per mesh and method) and fits (once per nu and Lmax) ----
    std::vector<MeshRecord> records(items.size());
    std::atomic<int> done{0};
    std::mutex io;
    const auto t_maps = std::chrono::steady_clock::now();
    parallel_for(static_cast<int>(items.size()), jobs, [&](int i) {
      omp_set_num_threads(1);
      MeshRecord& rec = records[static_cast<std::size_t>(i)];
      rec.file = items[static_cast<std::size_t>(i)].file;
      rec.label = items[static_cast<std::size_t>(i)].label;
      rec.methods.resize(method_enums.size());
      std::optional<PreparedMesh> prepared;
      try {
        prepared = prepare_for_mapping(read_mesh_file(rec.file).mesh);
        require_mappable(*prepared);
        rec.global = global_shape_descriptors(prepared->mesh);
      } catch (const WishError& e) {
        rec.refused = e.code();
      }
      std::string line = rec.file + ":";
      std::optional<SphericalMapResult> conformal;  // of the previous column, when it had the same method
      for (std::size_t m = 0; m < method_enums.size() && rec.refused.empty(); ++m) {
        MethodOutcome& out = rec.methods[m];
        if (m > 0 && method_enums[m] != method_enums[m - 1]) conformal.reset();
        SphericalMapOptions mo;
        mo.method = method_enums[m];
        // The recipe's own chain, as `wish train` runs it: its later attempts of the same method (cMCF continued past
        // its step cap, more Willmore steps) count, a map from another method is off-recipe and left out (what a
        // model with this recipe and the default policy, refuse, does with it): one method per row, no mixing.
        mo.fallback = true;
        mo.verification.max_conformal_p99 = max_k_p99;
        mo.flow_budget_seconds = flow_budget;
        mo.chain_budget_seconds = chain_budget;
        const auto t = std::chrono::steady_clock::now();
        try {
          if (!conformal)
            conformal = compute_spherical_map(prepared->mesh, mo, Deadline::after(std::chrono::duration<double>(map_seconds)));
          SphericalMapResult map = *conformal;
          if (correction_enums[m] != AreaCorrection::None && map.ok()) {
            // As compute_spherical_map does with options.area_correction, on the conformal map already computed.
            const auto tc = std::chrono::steady_clock::now();
            out.correction = spherical::equalize_sphere_density(map.sphere, prepared->mesh.vertices, prepared->mesh.faces,
                                                                mo.area_correction, mo.verification.degenerate_height);
            const MapQuality q = spherical::measure_map(prepared->mesh.vertices, prepared->mesh.faces, map.sphere, mo.verification);
            if (spherical::failed_map_check(q, mo.verification) != MapCheck::None) {
              map.status = MapStatus::VerificationFailed;
              map.failed_check = spherical::failed_map_check(q, mo.verification);
            }
            out.seconds = seconds_since(tc);  // the correction's own time (the conformal map's is in its row)
          } else {
            out.seconds = seconds_since(t);
          }
          if (!map.ok()) {
            out.failure = map.failed_check == MapCheck::None ? std::string(to_string(map.status)) : std::string(to_string(map.failed_check));
          } else if (map.method_used != mo.method) {
            out.failure = std::string("off_recipe_") + to_string(map.method_used);
          } else {
            for (double nu : nu_factors)
              for (int lmax : lmaxes) {
                ShFitOptions so;
                so.lmax = lmax;
                so.regularization = 1e-5 * nu;
                out.xi.push_back(fit_spherical_harmonics(prepared->mesh, map.sphere, so).invariants);
              }
            out.ok = true;
          }
        } catch (const WishError& e) {
          out.seconds = seconds_since(t);
          out.failure = e.code();
        }
        char buf[96];
        std::snprintf(buf, sizeof buf, " %s %s %.1fs", methods[m].c_str(), out.ok ? "ok" : out.failure.c_str(), out.seconds);
        line += buf;
      }
      if (!rec.refused.empty()) line += " refused [" + rec.refused + "]";
      const int n = ++done;
      std::lock_guard lock(io);
      std::fprintf(stderr, "[%d/%zu, %.0f s] %s\n", n, items.size(), seconds_since(t_maps), line.c_str());
    });
    if (dump.is_open())
      for (const auto& r : records)
        for (std::size_t m = 0; m < methods.size(); ++m) {
          if (!r.refused.empty() || !r.methods[m].ok) continue;
          for (std::size_t a = 0; a < nu_factors.size(); ++a)
            for (std::size_t b = 0; b < lmaxes.size(); ++b) {
              const Eigen::VectorXd& xi = r.methods[m].xi[a * lmaxes.size() + b];
              dump << dataset << "," << methods[m] << "," << r.file << "," << r.label << "," << nu_factors[a] << ","
                   << lmaxes[b];
              for (int l = 0; l <= lmax_top; ++l) {
                dump << ",";
                if (l < xi.size()) dump << xi(l);
              }
              for (Eigen::Index g = 0; g < r.global.size(); ++g) dump << "," << r.global(g);
              dump << "\n";
            }
        }
    dump.flush();

    // ---- map summary per method ----
    int refused = 0;
    std::map<std::string, int> refused_codes;
    for (const auto& r : records)
      if (!r.refused.empty()) {
        ++refused;
        ++refused_codes[r.refused];
      }
    std::printf("maps (%.0f s wall, %d jobs): %d meshes refused before mapping", seconds_since(t_maps), jobs, refused);
    for (const auto& [c, n] : refused_codes) std::printf(" [%s x%d]", c.c_str(), n);
    std::printf("\n%-12s %7s %9s %9s %9s  %s\n", "method", "mapped", "median s", "p95 s", "max s", "failures (check x count)");
    for (std::size_t m = 0; m < methods.size(); ++m) {
      std::vector<double> secs;
      std::map<std::string, int> fails;
      int ok = 0;
      for (const auto& r : records) {
        if (!r.refused.empty()) continue;
        secs.push_back(r.methods[m].seconds);
        if (r.methods[m].ok) ++ok;
        else ++fails[r.methods[m].failure];
      }
      std::sort(secs.begin(), secs.end());
      auto q = [&](double p) { return secs.empty() ? 0.0 : secs[std::min(secs.size() - 1, static_cast<std::size_t>(p * secs.size()))]; };
      std::string f;
      for (const auto& [c, n] : fails) f += c + " x" + std::to_string(n) + " ";
      std::printf("%-12s %3d/%-3zu %9.2f %9.2f %9.2f  %s\n", methods[m].c_str(), ok, secs.size(), q(0.5), q(0.95),
                  secs.empty() ? 0.0 : secs.back(), f.empty() ? "-" : f.c_str());
    }
    // ---- the area correction per corrected column: CPU s, iterations, |log area ratio| p99/max before -> after ----
    for (std::size_t m = 0; m < methods.size(); ++m) {
      if (correction_enums[m] == AreaCorrection::None) continue;
      std::vector<double> cpu, iters, p99b, p99a, maxb, maxa, kb, ka;
      std::map<std::string, int> stops;
      for (const auto& r : records) {
        if (!r.refused.empty() || r.methods[m].correction.method == AreaCorrection::None) continue;
        const AreaCorrectionReport& c = r.methods[m].correction;
        cpu.push_back(c.seconds);
        iters.push_back(c.iterations);
        p99b.push_back(c.before.log_ratio_p99);
        p99a.push_back(c.after.log_ratio_p99);
        maxb.push_back(c.before.log_ratio_max);
        maxa.push_back(c.after.log_ratio_max);
        ++stops[to_string(c.stop)];
      }
      auto med = [](std::vector<double> v, double p = 0.5) {
        if (v.empty()) return 0.0;
        std::sort(v.begin(), v.end());
        return v[std::min(v.size() - 1, static_cast<std::size_t>(p * v.size()))];
      };
      std::string st;
      for (const auto& [k, n] : stops) st += k + " x" + std::to_string(n) + " ";
      std::printf("%-12s correction on %zu maps: CPU s median %.2f p95 %.2f max %.2f; iterations median %.0f max %.0f; "
                  "|log area ratio| p99 median %.2f -> %.2f, max median %.2f -> %.2f; stops: %s\n",
                  methods[m].c_str(), cpu.size(), med(cpu), med(cpu, 0.95), cpu.empty() ? 0.0 : *std::max_element(cpu.begin(), cpu.end()),
                  med(iters), iters.empty() ? 0.0 : *std::max_element(iters.begin(), iters.end()), med(p99b), med(p99a),
                  med(maxb), med(maxa), st.c_str());
    }

    // ---- nested CV per configuration ----
    NestedCvOptions cv;
    cv.outer_folds = folds;
    cv.repeats = repeats;
    cv.inner_splits = 5;
    cv.grid.Cs = decade_grid(c_range[0], c_range[1]);
    cv.grid.gammas = decade_grid(gamma_range[0], gamma_range[1]);
    cv.grid.jobs = jobs;
    std::printf("\nnested CV accuracy %% (mean ± std over %d x %d outer folds; inner: 5 stratified shuffle splits, "
                "C 1e%d..1e%d, gamma 1e%d..1e%d)\n", repeats, folds, c_range[0], c_range[1], gamma_range[0], gamma_range[1]);
    std::printf("nu = 1e-5 x factor (SH fit default: factor 1; wish train default: factor 10^4); scale: xi(l)/xi(1); global alone is on the same meshes as the row\n");
    std::printf("%-12s %4s %7s %5s %5s %4s %12s %12s %12s\n", "method", "n", "nu x", "Lmax", "scale", "log", "xi alone",
                "global", "combined");
    const auto t_cv = std::chrono::steady_clock::now();
    struct Best {
      double score = -1;
      std::string what;
    } best_xi, best_comb;
    for (std::size_t m = 0; m < methods.size(); ++m) {
      std::vector<const MeshRecord*> used;
      for (const auto& r : records)
        if (r.refused.empty() && (paired ? std::all_of(r.methods.begin(), r.methods.end(), [](const MethodOutcome& x) { return x.ok; })
                                         : r.methods[m].ok))
          used.push_back(&r);
      std::map<std::string, int> per_class;
      for (const auto* r : used) ++per_class[r->label];
      std::printf("%-12s meshes per class:", methods[m].c_str());
      for (const auto& [label, n] : per_class) std::printf(" %s %d", label.c_str(), n);
      std::printf("%s\n", paired ? " (paired: mapped by every method)" : "");
      if (per_class.size() < 2 || std::any_of(per_class.begin(), per_class.end(), [](const auto& p) { return p.second < 2; })) {
        std::printf("%-12s %4zu  (too few mapped meshes per class for CV)\n", methods[m].c_str(), used.size());
        continue;
      }
      auto samples_for = [&](std::size_t k) {
        std::vector<TrainingSample> s;
        for (const auto* r : used) {
          TrainingSample t;
          t.id = r->file;
          t.label = r->label;
          t.features.invariants = r->methods[m].xi[k];
          t.features.global = r->global;
          s.push_back(std::move(t));
        }
        return s;
      };
      auto run_cv = [&](const std::vector<TrainingSample>& s, const FeatureSpec& spec) {
        Eigen::MatrixXd X;
        std::vector<int> y;
        std::vector<std::string> classes;
        build_feature_matrix(s, spec, X, y, classes);
        return score_of(nested_cross_validation(X, y, cv));
      };
      FeatureSpec gspec;
      gspec.family = FeatureFamily::Global;
      const Score global = run_cv(samples_for(0), gspec);
      if (csv.is_open())
        csv << dataset << "," << methods[m] << "," << used.size() << ",,,,,global," << global.mean << "," << global.std
            << "," << global.folds << "\n";
      for (std::size_t a = 0; a < nu_factors.size(); ++a)
        for (std::size_t b = 0; b < lmaxes.size(); ++b) {
          const auto samples = samples_for(a * lmaxes.size() + b);
          for (bool scale : scale_options)
            for (bool log : log_options) {
              FeatureSpec spec;
              spec.l_min = 1;
              spec.l_max = lmaxes[b];
              spec.scale = scale ? ScaleNormalization::ByFirstInvariant : ScaleNormalization::None;
              spec.log_transform = log;
              spec.family = FeatureFamily::Invariants;
              const Score xi = run_cv(samples, spec);
              spec.family = FeatureFamily::Combined;
              const Score comb = run_cv(samples, spec);
              std::printf("%-12s %4zu %7g %5d %5s %4s %12s %12s %12s\n", methods[m].c_str(), used.size(), nu_factors[a],
                          lmaxes[b], scale ? "xi1" : "-", log ? "log" : "-", pct(xi).c_str(), pct(global).c_str(),
                          pct(comb).c_str());
              std::fflush(stdout);
              char what[160];
              std::snprintf(what, sizeof what, "%s nu x%g Lmax %d scale %s log %s (n %zu, global %.1f)",
                            methods[m].c_str(), nu_factors[a], lmaxes[b], scale ? "xi1" : "none", log ? "on" : "off",
                            used.size(), 100 * global.mean);
              if (xi.mean > best_xi.score) best_xi = {xi.mean, what};
              if (comb.mean > best_comb.score) best_comb = {comb.mean, what};
              if (csv.is_open())
                for (const auto& [family, s] : {std::pair<const char*, Score>{"invariants", xi}, {"combined", comb}})
                  csv << dataset << "," << methods[m] << "," << used.size() << "," << nu_factors[a] << "," << lmaxes[b]
                      << "," << (scale ? "xi1" : "none") << "," << (log ? 1 : 0) << "," << family << "," << s.mean << ","
                      << s.std << "," << s.folds << "\n";
            }
        }
    }
    std::printf("best xi alone: %.1f %% — %s\n", 100 * best_xi.score, best_xi.what.c_str());
    std::printf("best combined: %.1f %% — %s\n", 100 * best_comb.score, best_comb.what.c_str());
    std::printf("(nested CV %.0f s)\n", seconds_since(t_cv));
  }
  return 0;
}
