// Training benchmark (issue 5): (1) the whole `wish train` path on the synthetic demo set — generate, describe
// (map + SH fit, parallel), grid search, fit, test split; (2) the grid search alone on a fixed descriptor CSV,
// ours against scikit-learn's GridSearchCV (bench/train_sklearn.py, Debian /usr/bin/python3) in the same run.
//   train_bench [--per-class N] [--lmax L] [--jobs J] [--csv DESCRIPTORS.csv] [--no-nested]
// With --csv, step (1) is skipped and the CSV is used for step (2); without it, step (1)'s descriptors are.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/pipeline/pipeline.hpp"
#include "core/synth/demo_dataset.hpp"
#include "core/training/descriptor_table.hpp"
#include "core/training/grid_search.hpp"
#include "core/training/training.hpp"

namespace {

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

}  // namespace

int main(int argc, char** argv) {
  int per_class = 12, lmax = 5, jobs = 2;
  bool nested = true;
  std::string csv;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--per-class" && i + 1 < argc) per_class = std::atoi(argv[++i]);
    else if (a == "--lmax" && i + 1 < argc) lmax = std::atoi(argv[++i]);
    else if (a == "--jobs" && i + 1 < argc) jobs = std::atoi(argv[++i]);
    else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
    else if (a == "--no-nested") nested = false;
    else {
      std::cerr << "usage: train_bench [--per-class N] [--lmax L] [--jobs J] [--csv FILE] [--no-nested]\n";
      return 2;
    }
  }
  using namespace wish;
  std::vector<TrainingSample> samples;
  wish::TrainOptions opts;
  opts.recipe.features.l_max = lmax;
  opts.recipe.features.log_transform = true;
  opts.recipe.sh.lmax = lmax;
  opts.grid.jobs = jobs;
  opts.nested_repeats = nested ? 2 : 0;
  if (csv.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    synth::DemoOptions demo;
    demo.per_class = per_class;
    const auto set = synth::generate_demo_set(demo);
    const double t_generate = seconds_since(t0);
    const auto t1 = std::chrono::steady_clock::now();
    PipelineOptions po;
    po.sh.lmax = lmax;
    po.compute_global_features = true;
    std::vector<std::optional<TrainingSample>> described(set.size());
    int failed = 0;
    parallel_for(static_cast<int>(set.size()), jobs, [&](int i) {
      try {
        const PipelineResult r = describe_mesh(set[static_cast<std::size_t>(i)].mesh, po);
        TrainingSample s;
        s.id = set[static_cast<std::size_t>(i)].name;
        s.label = set[static_cast<std::size_t>(i)].label;
        s.features.invariants = r.sh.invariants;
        s.features.global = r.features.global;
        described[static_cast<std::size_t>(i)] = std::move(s);
      } catch (const std::exception& e) {
        std::cerr << set[static_cast<std::size_t>(i)].name << ": " << e.what() << "\n";
      }
    });
    for (auto& s : described) s ? samples.push_back(std::move(*s)) : void(++failed);
    const double t_describe = seconds_since(t1);
    const auto t2 = std::chrono::steady_clock::now();
    const TrainingResult result = train_classifier(samples, opts);
    const double t_train = seconds_since(t2);
    std::printf("whole train on the demo set: %zu meshes (%d failed), %d jobs\n", set.size(), failed, jobs);
    std::printf("  generate %.2f s, describe %.2f s (%.3f s/mesh), train %.2f s (grid %.2f s, nested CV %.2f s)\n", t_generate,
                t_describe, t_describe / static_cast<double>(set.size()), t_train, result.report.grid.seconds,
                result.report.seconds_nested);
    std::printf("  best C %.0e gamma %.0e, grid %.3f, test %.3f, nested CV %.3f +- %.3f\n", result.report.grid.C(),
                result.report.grid.gamma(), result.report.grid.best_score, result.report.test.accuracy,
                result.report.nested.mean, result.report.nested.std);
    csv = (std::filesystem::temp_directory_path() / "wish_train_bench_descriptors.csv").string();
    std::ofstream(csv) << write_descriptor_table(samples);
  } else {
    std::ifstream in(csv);
    std::stringstream ss;
    ss << in.rdbuf();
    samples = read_descriptor_table(ss.str()).samples;
  }

  // Grid search alone: ours vs scikit-learn on the same descriptor CSV (same split count; own random splits).
  opts.nested_repeats = 0;
  const auto t3 = std::chrono::steady_clock::now();
  const TrainingResult ours = train_classifier(samples, opts);
  const double t_ours = seconds_since(t3);
  const std::filesystem::path script = std::filesystem::path(__FILE__).parent_path() / "train_sklearn.py";
  const std::string out = run("/usr/bin/python3 '" + script.string() + "' '" + csv + "' --lmax " + std::to_string(lmax) +
                              " --log --jobs " + std::to_string(jobs) + " 2>/dev/null");
  std::printf("\ngrid search 13 x 13 x 10 splits on %zu samples (xi 1..%d, log), %d jobs:\n", samples.size(), lmax, jobs);
  std::printf("  %-14s grid %7.2f s  train %7.2f s  best C %.0e gamma %.0e  grid %.3f  test %.3f\n", "wish (libsvm)",
              ours.report.grid.seconds, t_ours, ours.report.grid.C(), ours.report.grid.gamma(), ours.report.grid.best_score,
              ours.report.test.accuracy);
  try {
    const auto j = nlohmann::json::parse(out);
    std::printf("  %-14s grid %7.2f s  train %7.2f s  best C %.0e gamma %.0e  grid %.3f  test %.3f\n", "scikit-learn",
                j["grid_seconds"].get<double>(), j["train_seconds"].get<double>(), j["best_C"].get<double>(),
                j["best_gamma"].get<double>(), j["grid_score"].get<double>(), j["test_accuracy"].get<double>());
  } catch (const std::exception&) {
    std::printf("  scikit-learn: not available (/usr/bin/python3 with sklearn needed)\n");
  }
  return 0;
}
