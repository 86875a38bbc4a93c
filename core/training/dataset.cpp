#include "core/training/dataset.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <optional>

#include "core/classify/feature_pipeline.hpp"
#include "core/common/errors.hpp"
#include "core/common/thread_policy.hpp"
#include "core/io/volume_io.hpp"
#include "core/training/descriptor_table.hpp"
#include "core/training/grid_search.hpp"

namespace wish {
namespace fs = std::filesystem;

namespace {

std::string lower_name(const fs::path& p) {
  std::string name = p.filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return name;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

[[noreturn]] void bad_manifest(std::size_t line, const std::string& what) {
  throw InvalidInputError("invalid_manifest", "manifest line " + std::to_string(line) + ": " + what, {{"line", std::to_string(line)}});
}

}  // namespace

bool is_mesh_file_name(const fs::path& path) {
  const std::string n = lower_name(path);
  return ends_with(n, ".obj") || ends_with(n, ".ply") || ends_with(n, ".off") || ends_with(n, ".stl");
}

std::vector<DatasetItem> list_class_directories(const fs::path& root) {
  std::vector<DatasetItem> items;
  std::vector<fs::path> dirs;
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_directory()) dirs.push_back(e.path());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& d : dirs) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(d))
      if ((e.is_regular_file() && (is_mesh_file_name(e.path()) || is_volume_file_name(e.path()))) ||
          is_zarr_directory(e.path()))  // an OME-Zarr store is a directory
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) items.push_back({f.string(), d.filename().string(), {}});
  }
  return items;
}

std::vector<DatasetItem> read_dataset_manifest(const std::string& csv_text, const fs::path& base) {
  const auto rows = parse_csv(csv_text);
  std::vector<DatasetItem> items;
  std::map<std::string, std::size_t> volume_item;  // path -> index of its per-object item
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    if (row.size() == 1 && row[0].empty()) continue;  // blank line
    if (row.size() < 2 || row.size() > 3) bad_manifest(i + 1, "expected path,label[,label_id], got " + std::to_string(row.size()) + " fields");
    if (i == 0 && (row[0] == "path" || row[0] == "file")) continue;  // header
    fs::path p = row[0];
    if (p.is_relative()) p = base / p;
    const std::string path = p.lexically_normal().string();
    if (row[1].empty()) bad_manifest(i + 1, "empty label for '" + row[0] + "'");
    if (row.size() < 3 || row[2].empty()) {
      items.push_back({path, row[1], {}});
      continue;
    }
    std::uint32_t id = 0;
    const std::string& text = row[2];
    if (text.find_first_not_of("0123456789") != std::string::npos || text.size() > 10 ||
        std::stoull(text) > 0xffffffffull || std::stoull(text) == 0)
      bad_manifest(i + 1, "label_id '" + text + "' is not a positive integer label (1..4294967295)");
    id = static_cast<std::uint32_t>(std::stoull(text));
    auto [it, fresh] = volume_item.try_emplace(path, items.size());
    if (fresh) items.push_back({path, "", {}});
    auto& labels = items[it->second].object_labels;
    if (!labels.emplace(id, row[1]).second) bad_manifest(i + 1, "label_id " + text + " of '" + row[0] + "' listed twice");
  }
  return items;
}

TrainingSet describe_dataset(const std::vector<DatasetItem>& items, const ItemDescriber& describe,
                             const DescribeSetOptions& options) {
  std::vector<std::optional<ItemDescription>> results(items.size());
  std::atomic<int> done{0};
  std::mutex io;
  const auto start = std::chrono::steady_clock::now();
  limit_compute_threads_to_one();  // the BLAS setting is process-wide; OpenMP's is per thread (again per worker below)
  parallel_for(static_cast<int>(items.size()), options.jobs, [&](int i) {
    limit_compute_threads_to_one();
    const DatasetItem& item = items[static_cast<std::size_t>(i)];
    ItemDescription d;
    try {
      d = describe(item);
    } catch (const WishError& e) {
      d = {};
      if (item.object_labels.empty()) {
        d.losses.push_back({item.path, item.label, e.code(), e.what()});
      } else {  // the volume was not read: every object it was to give is lost
        for (const auto& [id, label] : item.object_labels)
          d.losses.push_back({item.path + "#" + std::to_string(id), label, e.code(), e.what()});
      }
      d.status = "FAILED [" + e.code() + "] " + e.what();
    }
    const int n = ++done;
    if (options.progress) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      char head[64];
      std::snprintf(head, sizeof head, "[%d/%zu, %.0f s] ", n, items.size(), elapsed);
      std::lock_guard lock(io);
      options.progress(head + item.path + ": " + d.status, !d.losses.empty());
    }
    results[static_cast<std::size_t>(i)] = std::move(d);
  });
  TrainingSet set;
  for (auto& r : results) {
    for (auto& s : r->samples) set.samples.push_back(std::move(s));
    for (auto& l : r->losses) set.losses.push_back(std::move(l));
  }
  return set;
}

std::vector<ClassLosses> summarize_training_set(const TrainingSet& set) {
  std::vector<std::string> kept, flagged;
  for (const auto& s : set.samples) {
    kept.push_back(s.label);
    if (s.off_recipe) flagged.push_back(s.label);
  }
  return summarize_losses(kept, set.losses, flagged);
}

FamilyScore family_score(const std::string& family, const TrainingReport& r) {
  FamilyScore s;
  s.family = family;
  s.features = r.feature_names.size();
  s.C = r.grid.C();
  s.gamma = r.grid.gamma();
  s.grid_score = r.grid.best_score;
  s.test_accuracy = r.test.accuracy;
  s.nested_mean = r.nested.mean;
  s.nested_std = r.nested.std;
  s.nested_scores = r.nested.scores;
  s.nested_inner_scores = r.nested.inner_scores;
  return s;
}

std::vector<FamilyScore> compare_feature_families(const std::vector<TrainingSample>& samples, const TrainOptions& options,
                                                  const TrainingReport& trained,
                                                  const std::function<void(const std::string&)>& on_family) {
  const std::string own = to_string(options.recipe.features.family);
  std::vector<FamilyScore> rows{family_score(own, trained)};
  for (const char* family : {"invariants", "global", "combined"}) {
    if (family == own) continue;
    TrainOptions u = options;
    u.recipe.features.family = feature_family_from_name(family);
    u.progress = nullptr;
    u.probability = false;  // the comparison keeps figures, not models: no Platt fit, no novelty calibration
    u.novelty = false;
    if (on_family) on_family(family);
    rows.push_back(family_score(family, train_classifier(samples, u).report));
  }
  return rows;
}

}  // namespace wish
