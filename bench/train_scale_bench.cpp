// Training that scales (issues 25 and 40): the default `wish train` (test split, search, final fit, nested CV, the
// feature-family comparison) on generated descriptor sets of 1,000 to 30,000 rows, with the path it took (full grid or
// successive halving; nested CV repeats), against the paper's full grid on the same rows and splits where that is
// feasible, and scikit-learn's GridSearchCV and HalvingGridSearchCV (bench/train_scale_sklearn.py, Debian
// /usr/bin/python3) on the same rows, hold-out and validation splits, in the same run.
//   train_scale_bench [--sizes 1000,3000,10000,30000] [--jobs 2]
//                     [--whole-max N (default whole train, 30000)] [--paper-whole-max N (whole train, full grid and
//                     nested CV 2 x 5 as before issue 40, 0)] [--exhaustive-max N (whole train, every cell, 0)]
//                     [--full-grid-max N (search + fit + test, full grid, 3000)] [--grid-exhaustive-max N (0)]
//                     [--sklearn-max N (GridSearchCV, 3000)] [--sklearn-halving-max N (HalvingGridSearchCV, 30000)]
//                     [--sklearn-seconds S (scikit-learn wall limit per run, 3600)]
//                     [--search auto|grid|halving] [--halving-rows N] [--halving-above N]
//                     [--two-class N [--classes A,B] [--two-class-spread S]] [--spread S] [--csv REAL.csv ...] [--patience P]
//   train_scale_bench --sizes 10000 [--two-class 1758] --save-sets DIR: write the sets as descriptor CSVs (for `wish train`)
//   train_scale_bench --sizes 1000 --profile FAMILY [--profile-exhaustive]: per cell CPU seconds and score of one grid
// Descriptor sets: drawn from the synthetic demo set's descriptors (data/models/demo-descriptors.csv): per class a
// Gaussian fitted to [log xi(1..10), global descriptors] (covariance shrunk 20 % to its diagonal), widened by
// --spread (default 1.5: the classes overlap more than in the demo set, as real ones do). --two-class N adds a set of
// N rows of two classes (--classes, default astrocyte,endothelium; widened by --two-class-spread, default 3, so that
// they overlap as hard classes do): the stand-in for issue 40's 1,758 CT organ masks of two classes. --csv adds real labelled descriptor tables (e.g. `wish describe --csv` of UroCell meshes with a
// label column) as extra rows.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <sys/resource.h>
#include <unistd.h>
#include <string>

#include <Eigen/Cholesky>
#include <nlohmann/json.hpp>

#include "core/classify/feature_pipeline.hpp"
#include "core/classify/global_descriptors.hpp"
#include "core/classify/splits.hpp"
#include "core/classify/standard_scaler.hpp"
#include "core/training/dataset.hpp"
#include "core/training/descriptor_table.hpp"
#include "core/training/grid_search.hpp"
#include "core/training/search_plan.hpp"
#include "core/training/training.hpp"

namespace {

using namespace wish;
namespace fs = std::filesystem;

// CPU seconds of this process (all threads) or of its waited-for children: the figure that survives a loaded
// machine; on an idle machine with J cores the wall time of a J-thread run is about CPU / J.
double cpu_seconds(int who = RUSAGE_SELF) {
  rusage u{};
  getrusage(who, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string run(const std::string& cmd) {
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  return out;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// n samples, classes of the template in equal shares, from per-class Gaussians in [log xi(1..L), global].
std::vector<TrainingSample> generate(const std::vector<TrainingSample>& templ, int n, double spread, std::uint64_t seed) {
  std::map<std::string, std::vector<const TrainingSample*>> by_class;
  for (const auto& s : templ) by_class[s.label].push_back(&s);
  const int L = static_cast<int>(templ.front().features.invariants.size()) - 1;
  const int G = static_cast<int>(templ.front().features.global.size());
  const int d = L + G;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<TrainingSample> out;
  const int k = static_cast<int>(by_class.size());
  int c = 0;
  for (const auto& [label, members] : by_class) {
    Eigen::MatrixXd Z(static_cast<Eigen::Index>(members.size()), d);
    for (std::size_t i = 0; i < members.size(); ++i) {
      for (int l = 1; l <= L; ++l) Z(static_cast<Eigen::Index>(i), l - 1) = std::log(members[i]->features.invariants(l));
      for (int g = 0; g < G; ++g) Z(static_cast<Eigen::Index>(i), L + g) = members[i]->features.global(g);
    }
    const Eigen::RowVectorXd mean = Z.colwise().mean();
    const Eigen::MatrixXd centred = Z.rowwise() - mean;
    Eigen::MatrixXd cov = centred.transpose() * centred / std::max<double>(1.0, static_cast<double>(members.size()) - 1);
    cov = 0.8 * cov + 0.2 * Eigen::MatrixXd(cov.diagonal().asDiagonal());
    cov += 1e-9 * Eigen::MatrixXd::Identity(d, d);
    const Eigen::MatrixXd chol = Eigen::LLT<Eigen::MatrixXd>(cov * spread * spread).matrixL();
    const int count = n / k + (c < n % k ? 1 : 0);
    for (int i = 0; i < count; ++i) {
      Eigen::VectorXd z(d);
      for (int j = 0; j < d; ++j) z(j) = normal(rng);
      const Eigen::VectorXd v = mean.transpose() + chol * z;
      TrainingSample s;
      s.label = label;
      s.id = label + "/gen_" + std::to_string(i) + ".ply";
      s.features.invariants.resize(L + 1);
      s.features.invariants(0) = members.front()->features.invariants(0);
      for (int l = 1; l <= L; ++l) s.features.invariants(l) = std::exp(v(l - 1));
      s.features.global = v.tail(G);
      s.features.global(kGlobalArea) = std::abs(s.features.global(kGlobalArea)) + 1e-3;
      out.push_back(std::move(s));
    }
    ++c;
  }
  return out;
}

struct WholeRun {
  double seconds = 0, cpu = 0, test = 0, nested = 0, grid_score = 0, C = 0, gamma = 0;
  std::optional<Interval> interval;
  std::string path;
  int fits = 0, capped = 0, skipped = 0, search_rows = 0;
  std::vector<FamilyScore> families;
};

// "halving, 1 x 5" : the search that ran and the nested CV's repeats x folds.
std::string path_of(const TrainingReport& r) {
  std::string p = r.grid.method + " (" + std::to_string(r.grid.search_rows) + " rows)";
  if (!r.nested.scores.empty()) p += ", nested " + std::to_string(r.nested.repeats) + " x " + std::to_string(r.nested.outer_folds);
  return p;
}

// The default `wish train` from a descriptor table: train_classifier + the family comparison (as cmd_train.cpp).
WholeRun whole_train(const std::vector<TrainingSample>& samples, TrainOptions t, bool compare) {
  WholeRun w;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  const TrainingResult r = train_classifier(samples, t);
  w.families = compare ? compare_feature_families(samples, t, r.report) : std::vector<FamilyScore>{family_score("invariants", r.report)};
  w.seconds = seconds_since(t0);
  w.cpu = cpu_seconds() - c0;
  w.test = r.report.test.accuracy;
  w.nested = r.report.nested.mean;
  w.interval = r.report.nested.interval95;
  w.grid_score = r.report.grid.best_score;
  w.C = r.report.grid.C();
  w.gamma = r.report.grid.gamma();
  w.path = path_of(r.report);
  w.search_rows = r.report.grid.search_rows;
  w.fits = r.report.grid.fits + r.report.nested.fits;
  w.capped = r.report.grid.total_capped_fits() + r.report.nested.capped_fits;
  w.skipped = r.report.grid.cells_skipped + r.report.nested.cells_skipped;
  return w;
}

int g_patience = 0;
ScalePolicy g_scale;

TrainOptions default_options(int jobs) {
  TrainOptions t;  // the defaults of `wish train` (cli/cmd_train.cpp): Lmax 10, log, invariants
  t.recipe.features.l_max = 10;
  t.recipe.features.log_transform = true;
  t.recipe.sh.lmax = 10;
  t.grid.jobs = jobs;
  if (g_patience > 0) t.grid.early_stop_patience = g_patience;
  t.scale = g_scale;
  t.trained_at = "2024-01-01T00:00:00Z";
  return t;
}

void print_whole(const std::string& name, std::size_t n, const WholeRun& w) {
  char interval[64] = "";
  if (w.interval) std::snprintf(interval, sizeof interval, " (%.3f-%.3f)", w.interval->low, w.interval->high);
  std::printf("| %s | %zu | %s | %.1f | %.1f | %.3f | %.3f%s | %.0e / %.0e | %d | %d |", name.c_str(), n, w.path.c_str(),
              w.seconds, w.cpu, w.test, w.nested, interval, w.C, w.gamma, w.fits, w.capped);
  for (const auto& f : w.families) std::printf(" %s %.3f", f.family.c_str(), f.nested_mean);
  std::printf(" |\n");
  std::fflush(stdout);
}

// Where a grid search's time goes: per cell (C down, gamma across) the CPU seconds of its split fits and the mean
// validation accuracy, on the hold-out training rows of train_classifier, for the given family.
void profile_grid(const std::vector<TrainingSample>& samples, TrainOptions t, const std::string& family) {
  t.recipe.features.family = feature_family_from_name(family);
  Eigen::MatrixXd X;
  std::vector<int> y;
  std::vector<std::string> classes;
  build_feature_matrix(samples, t.recipe.features, X, y, classes);
  const Split holdout = stratified_shuffle_split(y, 1, t.test_fraction, t.seed).front();
  Eigen::MatrixXd Xa(static_cast<Eigen::Index>(holdout.train.size()), X.cols());
  std::vector<int> ya;
  for (std::size_t i = 0; i < holdout.train.size(); ++i) {
    Xa.row(static_cast<Eigen::Index>(i)) = X.row(holdout.train[i]);
    ya.push_back(y[holdout.train[i]]);
  }
  const Eigen::MatrixXd Xs = StandardScaler::fit(Xa).transform(Xa);
  const auto splits = stratified_shuffle_split(ya, t.grid_splits, t.grid_validation_fraction, t.seed + 1);
  const double c0 = cpu_seconds();
  const GridSearchResult r = grid_search(Xs, ya, splits, t.grid);
  std::printf("## profile %s n=%zu: %.1f CPU s, wall %.1f s, best %.0e/%.0e %.4f, fits %d capped %d skipped %d\n",
              family.c_str(), samples.size(), cpu_seconds() - c0, r.seconds, r.C(), r.gamma(), r.best_score, r.fits,
              r.total_capped_fits(), r.cells_skipped);
  for (int ci = 0; ci < static_cast<int>(r.Cs.size()); ++ci) {
    std::printf("C=%6.0e |", r.Cs[ci]);
    for (int gi = 0; gi < static_cast<int>(r.gammas.size()); ++gi)
      std::printf(" %5.1f/%.3f%s", r.cell_cpu_seconds(ci, gi), r.mean_score(ci, gi), r.capped_fits(ci, gi) ? "!" : " ");
    std::printf("\n");
  }
  std::fflush(stdout);
}

// One scikit-learn run (train_scale_sklearn.py --search grid|halving) on the rows, hold-out and validation splits of
// train_classifier; prints a row of the search table or says why there is none.
void sklearn_row(const std::vector<TrainingSample>& samples, const std::string& set_name, const TrainOptions& t,
                 const std::string& search, int jobs, int limit_seconds, const fs::path& script, const fs::path& tmp) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  std::vector<std::string> classes;
  build_feature_matrix(samples, t.recipe.features, X, y, classes);
  const Split holdout = stratified_shuffle_split(y, 1, t.test_fraction, t.seed).front();
  std::vector<int> y_train;
  for (int i : holdout.train) y_train.push_back(y[i]);
  const auto grid_splits = stratified_shuffle_split(y_train, t.grid_splits, t.grid_validation_fraction, t.seed + 1);
  nlohmann::json spec;
  spec["labels"] = y;
  spec["holdout"] = {{"train", holdout.train}, {"test", holdout.test}};
  for (const auto& s : grid_splits) spec["grid_splits"].push_back({{"train", s.train}, {"test", s.test}});
  const fs::path csv = tmp / "descriptors.csv", splits = tmp / "splits.json";
  std::ofstream(csv) << write_descriptor_table(samples);
  std::ofstream(splits) << spec.dump();
  const std::string name = search == "halving" ? "scikit-learn HalvingGridSearchCV" : "scikit-learn GridSearchCV";
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds(RUSAGE_CHILDREN);
  const std::string out = run("timeout " + std::to_string(limit_seconds) + " /usr/bin/python3 '" + script.string() + "' '" +
                              csv.string() + "' '" + splits.string() + "' --jobs " + std::to_string(jobs) + " --search " +
                              search + " 2>/dev/null");
  const double wall = seconds_since(t0), cpu = cpu_seconds(RUSAGE_CHILDREN) - c0;
  try {
    const auto j = nlohmann::json::parse(out);
    std::string path = search;
    if (search == "halving") {
      path += " (rows";
      for (const auto& r : j["n_resources"]) path += " " + std::to_string(r.get<int>());
      path += ")";
    }
    std::printf("| %s (%s) | %zu | %s | %.1f | %.1f | %.3f | %.0e / %.0e | %.3f | %d | — |\n", name.c_str(), set_name.c_str(),
                samples.size(), path.c_str(), wall, cpu, j["grid_score"].get<double>(), j["best_C"].get<double>(),
                j["best_gamma"].get<double>(), j["test_accuracy"].get<double>(), j["fits"].get<int>());
  } catch (const std::exception&) {
    std::printf("| %s (%s) | %zu | %s | not finished (%.0f s wall, %.0f CPU s; scikit-learn missing or past the %d s limit) |\n",
                name.c_str(), set_name.c_str(), samples.size(), search.c_str(), wall, cpu, limit_seconds);
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // rows survive a run stopped for time
  std::vector<int> sizes{1000, 3000, 10000, 30000};
  std::vector<std::string> real_csvs;
  int jobs = 2, whole_max = 30000, paper_whole_max = 0, exhaustive_max = 0, full_grid_max = 3000, grid_exhaustive_max = 0;
  int sklearn_max = 3000, sklearn_halving_max = 30000, sklearn_seconds = 3600, two_class = 0;
  std::string two_classes = "astrocyte,endothelium";
  std::string save_sets;  // a directory: each generated set written as a descriptor CSV (for `wish train` itself)
  double spread = 1.5, two_class_spread = 3.0;
  std::string profile_family;
  int patience = 0;  // 0: the default of GridSearchOptions
  bool profile_exhaustive = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
    if (a == "--sizes") {
      sizes.clear();
      std::stringstream ss(next());
      for (std::string item; std::getline(ss, item, ',');) sizes.push_back(std::stoi(item));
    } else if (a == "--jobs") jobs = std::stoi(next());
    else if (a == "--whole-max") whole_max = std::stoi(next());
    else if (a == "--paper-whole-max") paper_whole_max = std::stoi(next());
    else if (a == "--exhaustive-max") exhaustive_max = std::stoi(next());
    else if (a == "--full-grid-max") full_grid_max = std::stoi(next());
    else if (a == "--grid-exhaustive-max") grid_exhaustive_max = std::stoi(next());
    else if (a == "--sklearn-max") sklearn_max = std::stoi(next());
    else if (a == "--sklearn-halving-max") sklearn_halving_max = std::stoi(next());
    else if (a == "--sklearn-seconds") sklearn_seconds = std::stoi(next());
    else if (a == "--search") g_scale.search = search_method_from_name(next());
    else if (a == "--halving-rows") g_scale.halving.max_rows = std::stoi(next());
    else if (a == "--halving-above") g_scale.halving_above_rows = std::stoi(next());
    else if (a == "--two-class") two_class = std::stoi(next());
    else if (a == "--save-sets") save_sets = next();
    else if (a == "--classes") two_classes = next();
    else if (a == "--two-class-spread") two_class_spread = std::stod(next());
    else if (a == "--spread") spread = std::stod(next());
    else if (a == "--csv") real_csvs.push_back(next());
    else if (a == "--profile") profile_family = next();
    else if (a == "--patience") patience = std::stoi(next());
    else if (a == "--profile-exhaustive") profile_exhaustive = true;
    else {
      std::cerr << "usage: train_scale_bench [--sizes 1000,3000,10000,30000] [--jobs J] [--whole-max N] "
                   "[--paper-whole-max N] [--exhaustive-max N] [--full-grid-max N] [--grid-exhaustive-max N] "
                   "[--sklearn-max N] [--sklearn-halving-max N] [--sklearn-seconds S] [--search auto|grid|halving] "
                   "[--halving-rows N] [--halving-above N] [--two-class N [--classes A,B] [--two-class-spread S]] "
                   "[--spread S] [--csv REAL.csv ...] [--patience P] [--profile FAMILY [--profile-exhaustive]] [--save-sets DIR]\n";
      return 2;
    }
  }
  g_patience = patience;
  const fs::path project_data = WISH_PROJECT_DATA_DEFAULT;
  const auto templ = read_descriptor_table(read_text(project_data / "models" / "demo-descriptors.csv")).samples;
  struct Set {
    std::string name;
    std::vector<TrainingSample> samples;
  };
  std::vector<Set> sets;
  for (int n : sizes) sets.push_back({"generated", generate(templ, n, spread, 1000 + static_cast<std::uint64_t>(n))});
  if (two_class > 0) {
    std::vector<TrainingSample> pair;
    for (const auto& s : templ)
      if (("," + two_classes + ",").find("," + s.label + ",") != std::string::npos) pair.push_back(s);
    sets.push_back({"two-class", generate(pair, two_class, two_class_spread, 2000 + static_cast<std::uint64_t>(two_class))});
  }
  for (const auto& p : real_csvs) sets.push_back({fs::path(p).filename().string(), read_descriptor_table(read_text(p)).samples});
  if (!save_sets.empty()) {
    fs::create_directories(save_sets);
    for (const auto& set : sets) {
      const fs::path out = fs::path(save_sets) / (set.name + "-" + std::to_string(set.samples.size()) + ".csv");
      std::ofstream(out) << write_descriptor_table(set.samples);
      std::printf("wrote %s\n", out.c_str());
    }
    return 0;
  }
  if (!profile_family.empty()) {
    for (const auto& set : sets) {
      TrainOptions t = default_options(jobs);
      if (profile_exhaustive) t.grid.precomputed_kernel = t.grid.early_stop = false;
      profile_grid(set.samples, t, profile_family);
    }
    return 0;
  }
  // Not __FILE__: with a compiler cache's base directory it is relative to the build directory.
  const fs::path script = project_data.parent_path() / "bench" / "train_scale_sklearn.py";
  const fs::path tmp = fs::temp_directory_path() / ("wish_train_scale_" + std::to_string(::getpid()));
  fs::create_directories(tmp);

  std::printf("## whole `wish train` (test split, search, final fit, nested CV, the 3 feature families), %d jobs\n\n", jobs);
  std::printf("| run | n | path: search (rows of its best score), nested CV repeats x folds | wall s | CPU s | test acc | "
              "nested CV (95 %% interval) | best C / gamma | fits | capped fits | nested CV per family |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& set : sets) {
    const std::size_t n = set.samples.size();
    const bool compare = set.samples.front().features.global.size() > 0;
    TrainOptions t = default_options(jobs);
    if (static_cast<int>(n) <= whole_max) print_whole("default (" + set.name + ")", n, whole_train(set.samples, t, compare));
    t.scale.search = SearchMethod::Grid;  // the paper's protocol, the default before issue 40
    if (static_cast<int>(n) <= paper_whole_max) print_whole("full grid, 2 x 5 (" + set.name + ")", n, whole_train(set.samples, t, compare));
    if (static_cast<int>(n) <= exhaustive_max) {
      t.grid.precomputed_kernel = false;
      t.grid.early_stop = false;
      print_whole("exhaustive (" + set.name + ")", n, whole_train(set.samples, t, compare));
    }
  }

  std::printf("\n## search + final fit (Platt) + test split, same rows, hold-out and 10 validation splits, %d jobs\n\n", jobs);
  std::printf("| search | n | path | wall s | CPU s | score (rows) | best C / gamma | test acc | fits | capped fits |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& set : sets) {
    const std::size_t n = set.samples.size();
    TrainOptions t = default_options(jobs);
    t.nested_repeats = 0;
    t.novelty = false;  // scikit-learn's side has none
    auto row = [&](const std::string& name, const TrainOptions& o) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpu_seconds();
      const TrainingResult r = train_classifier(set.samples, o);
      std::string path = r.report.grid.method;
      if (!r.report.grid.rungs.empty()) {
        path += " (rows:cells:s";
        for (const auto& g : r.report.grid.rungs)
          path += " " + std::to_string(g.rows) + ":" + std::to_string(g.candidates) + ":" + std::to_string(std::lround(g.seconds));
        path += ")";
      }
      std::printf("| %s (%s) | %zu | %s | %.1f | %.1f | %.3f (%d) | %.0e / %.0e | %.3f | %d | %d |\n", name.c_str(),
                  set.name.c_str(), n, path.c_str(), seconds_since(t0), cpu_seconds() - c0,
                  r.report.grid.best_score, r.report.grid.search_rows, r.report.grid.C(), r.report.grid.gamma(),
                  r.report.test.accuracy, r.report.grid.fits, r.report.grid.total_capped_fits());
      std::fflush(stdout);
    };
    row("default", t);
    if (static_cast<int>(n) <= full_grid_max) {
      TrainOptions g = t;
      g.scale.search = SearchMethod::Grid;
      row("full grid", g);
    }
    if (static_cast<int>(n) <= grid_exhaustive_max) {
      TrainOptions e = t;
      e.scale.search = SearchMethod::Grid;
      e.grid.precomputed_kernel = false;
      e.grid.early_stop = false;
      row("exhaustive", e);
    }
    if (static_cast<int>(n) <= sklearn_max) sklearn_row(set.samples, set.name, t, "grid", jobs, sklearn_seconds, script, tmp);
    if (static_cast<int>(n) <= sklearn_halving_max)
      sklearn_row(set.samples, set.name, t, "halving", jobs, sklearn_seconds, script, tmp);
  }
  fs::remove_all(tmp);
  return 0;
}
