#pragma once
// Stratified resampling for model selection and evaluation (paper §6: scikit-learn's StratifiedShuffleSplit and
// a stratified 20 % test split; docs/design/classification.md: nested, repeated stratified cross-validation).
// Deterministic for a seed on every platform: our own shuffle on std::mt19937_64 (the standard distributions are
// implementation-defined). Not bit-compatible with numpy's permutations; parity tests pass the splits explicitly.

#include <cstdint>
#include <vector>

namespace wish {

struct Split {
  std::vector<int> train, test;  // sample indices, ascending
};

// n_splits random stratified train/test partitions; each class contributes about test_fraction of its samples
// to test (per-class counts by largest remainder, as scikit-learn's _approximate_mode), at least one sample per
// class stays in train. Throws InvalidInputError("training_data") when a split cannot hold every class.
std::vector<Split> stratified_shuffle_split(const std::vector<int>& labels, int n_splits, double test_fraction,
                                            std::uint64_t seed);

// k folds, classes dealt round-robin after a per-class shuffle; returns k splits (test = one fold).
std::vector<Split> stratified_k_fold(const std::vector<int>& labels, int k, std::uint64_t seed);

// Uniform integer in [0, n) from a 64-bit generator state (splitmix64), portable.
std::uint64_t splitmix64(std::uint64_t& state);

// Fisher-Yates shuffle on splitmix64 with exact uniform draws (rejection sampling), the one the splits use.
void shuffle_indices(std::vector<int>& v, std::uint64_t& state);

}  // namespace wish
