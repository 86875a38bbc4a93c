#include "core/classify/splits.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>

#include "core/common/errors.hpp"

namespace wish {
namespace {

std::uint64_t below(std::uint64_t& state, std::uint64_t n) {
  // Rejection sampling: exact uniform on [0, n).
  const std::uint64_t limit = ~std::uint64_t{0} - (~std::uint64_t{0} % n);
  std::uint64_t r;
  do r = splitmix64(state);
  while (r >= limit);
  return r % n;
}

std::map<int, std::vector<int>> by_class(const std::vector<int>& labels) {
  std::map<int, std::vector<int>> groups;
  for (int i = 0; i < static_cast<int>(labels.size()); ++i) groups[labels[i]].push_back(i);
  return groups;
}

}  // namespace

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

void shuffle_indices(std::vector<int>& v, std::uint64_t& state) {
  for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[below(state, i)]);
}

std::vector<Split> stratified_shuffle_split(const std::vector<int>& labels, int n_splits, double test_fraction,
                                            std::uint64_t seed) {
  const auto groups = by_class(labels);
  const int n = static_cast<int>(labels.size());
  const int n_test = static_cast<int>(std::ceil(test_fraction * n));
  const int n_classes = static_cast<int>(groups.size());
  if (n_test < n_classes || n - n_test < n_classes)
    throw InvalidInputError("training_data",
                            "a stratified split of " + std::to_string(n) + " samples with test fraction " +
                                std::to_string(test_fraction) + " cannot hold all " + std::to_string(n_classes) +
                                " classes on both sides");
  // Per-class test counts: floor of the proportional share, the remainder to the largest fractional parts
  // (ties: the larger class, then the lower label), never taking a class's last sample.
  std::vector<int> class_label, class_size, take;
  std::vector<double> frac;
  for (const auto& [label, members] : groups) {
    const double share = static_cast<double>(n_test) * members.size() / n;
    class_label.push_back(label);
    class_size.push_back(static_cast<int>(members.size()));
    take.push_back(std::min(static_cast<int>(std::floor(share)), static_cast<int>(members.size()) - 1));
    frac.push_back(share - std::floor(share));
  }
  int remaining = n_test - std::accumulate(take.begin(), take.end(), 0);
  std::vector<int> order(n_classes);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (frac[a] != frac[b]) return frac[a] > frac[b];
    return class_size[a] > class_size[b];
  });
  while (remaining > 0) {
    bool progressed = false;
    for (int c : order) {
      if (remaining == 0) break;
      if (take[c] < class_size[c] - 1) {
        ++take[c];
        --remaining;
        progressed = true;
      }
    }
    if (!progressed) break;
  }
  std::vector<Split> splits;
  std::uint64_t state = seed;
  for (int s = 0; s < n_splits; ++s) {
    Split split;
    int c = 0;
    for (const auto& [label, members] : groups) {
      std::vector<int> shuffled = members;
      shuffle_indices(shuffled, state);
      split.test.insert(split.test.end(), shuffled.begin(), shuffled.begin() + take[c]);
      split.train.insert(split.train.end(), shuffled.begin() + take[c], shuffled.end());
      ++c;
    }
    std::sort(split.train.begin(), split.train.end());
    std::sort(split.test.begin(), split.test.end());
    splits.push_back(std::move(split));
  }
  return splits;
}

std::vector<Split> stratified_k_fold(const std::vector<int>& labels, int k, std::uint64_t seed) {
  if (k < 2 || k > static_cast<int>(labels.size()))
    throw InvalidInputError("training_data", "k-fold needs 2 <= k <= #samples (k = " + std::to_string(k) + ")");
  std::vector<std::vector<int>> folds(k);
  std::uint64_t state = seed;
  int next = 0;  // continue dealing where the previous class stopped, so folds stay balanced in size
  for (const auto& [label, members] : by_class(labels)) {
    std::vector<int> shuffled = members;
    shuffle_indices(shuffled, state);
    for (int i : shuffled) folds[next++ % k].push_back(i);
  }
  std::vector<Split> splits(k);
  for (int f = 0; f < k; ++f) {
    for (int g = 0; g < k; ++g) {
      auto& dst = g == f ? splits[f].test : splits[f].train;
      dst.insert(dst.end(), folds[g].begin(), folds[g].end());
    }
    std::sort(splits[f].train.begin(), splits[f].train.end());
    std::sort(splits[f].test.begin(), splits[f].test.end());
  }
  return splits;
}

}  // namespace wish
