#pragma once
// Per-pixel deterministic sample streams. Every (pixel, sample index, dimension)
// maps to the same number whatever thread renders it, so an image depends on the
// seed only. Numbers are drawn four at a time ("4D patterns", Burley 2020 §4).
//   Sobol:       Owen-scrambled, shuffled Sobol (Burley, "Practical Hash-based Owen
//                Scrambling", JCGT 2020): the first four Sobol dimensions, each
//                scrambled with a per-pattern seed, and the sample index itself
//                shuffled by a nested uniform scramble so that patterns decorrelate.
//   Independent: a counter-based hash per (pixel, index, pattern, dimension).
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

namespace plumage {

enum class SamplerKind { Sobol, Independent };
inline constexpr SamplerKind kSamplerKinds[] = {SamplerKind::Sobol, SamplerKind::Independent};
const char* to_string(SamplerKind k);
SamplerKind parse_sampler_kind(const std::string& s);  // "sobol" | "independent"

// Burley 2020, listing 2-3: reverse bits, Laine-Karras hash permutation, reverse back.
std::uint32_t nested_uniform_scramble(std::uint32_t x, std::uint32_t seed);
// The d-th (0..3) Sobol dimension of index i, as a 32-bit fixed-point fraction.
std::uint32_t sobol(std::uint32_t i, int d);
// A well-mixed 32-bit hash of a and b.
std::uint32_t hash_combine(std::uint32_t a, std::uint32_t b);
// A hash's top 24 bits as a float in [0, 1) (a float cannot hold more below 1).
inline float to_unit(std::uint32_t x) { return float(x >> 8) * 0x1p-24f; }

class PixelSampler {
 public:
  PixelSampler(SamplerKind kind, std::uint64_t seed) : kind_(kind), seed_(std::uint32_t(seed ^ (seed >> 32))) {}

  // Starts the stream of sample `index` of pixel (x, y).
  void start(int x, int y, std::uint32_t index);
  // The next four numbers in [0, 1).
  glm::vec4 next4();
  // The first two of the next four (the same numbers next4 would give, for half
  // the work; the stream moves on by a whole pattern).
  glm::vec2 next2();

  SamplerKind kind() const { return kind_; }

 private:
  SamplerKind kind_;
  std::uint32_t seed_;
  std::uint32_t pixel_seed_ = 0;
  std::uint32_t index_ = 0;
  std::uint32_t reversed_index_ = 0;
  std::uint32_t pattern_ = 0;

  template <int D>
  void draw(float* out);
};

}  // namespace plumage
