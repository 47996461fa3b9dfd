#pragma once
// The generator's random numbers: std::mt19937_64 (its output is fixed by the
// C++ standard) mapped to [0,1) by our own arithmetic, because the standard
// library's distributions differ between implementations and a seed must give
// the same feather everywhere.
#include <cstdint>
#include <random>

namespace plumage {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  // Uniform in [0,1): the top 53 bits of one draw, scaled by 2^-53.
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }
  // Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform in [-1, 1).
  double symmetric() { return 2.0 * uniform() - 1.0; }
  // An independent stream for a named sub-task (splitmix64 of seed and tag),
  // so adding draws in one part of the generator does not shift another part.
  static std::uint64_t derive(std::uint64_t seed, std::uint64_t tag) {
    std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (tag + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace plumage
