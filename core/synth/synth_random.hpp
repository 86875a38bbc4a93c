#pragma once
// Portable deterministic random numbers for the demo generator: splitmix64 plus our own uniform/normal
// transforms (std:: distributions are implementation-defined, so they would break "same seed -> same bytes"
// across standard libraries).

#include <cmath>
#include <cstdint>

namespace wish::synth {

class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  double normal() {  // Box-Muller
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * 3.14159265358979323846 * u2);
  }
  int below(int n) { return static_cast<int>(uniform() * n); }

 private:
  std::uint64_t state_;
};

// A seed for (base, a, b) that does not correlate with neighbouring indices.
inline std::uint64_t mix_seed(std::uint64_t base, std::uint64_t a, std::uint64_t b = 0) {
  Random r(base ^ (a * 0xd1342543de82ef95ull) ^ (b * 0x9e3779b97f4a7c15ull));
  r.next();
  return r.next();
}

}  // namespace wish::synth
