#include "plumage/renderer/sampler.h"

#include <array>
#include <bit>

#include "plumage/common/error.h"

namespace plumage {
namespace {

// 32-bit Sobol direction numbers for dimensions 0..3. Dimension 0 is the van der
// Corput sequence; the others come from the primitive polynomials and initial
// numbers m_k of Joe & Kuo (2008): (s=1, a=0, m=1), (s=2, a=1, m=1,3), (s=3, a=1, m=1,3,1).
struct SobolMatrices {
  std::array<std::array<std::uint32_t, 32>, 4> v{};
  SobolMatrices() {
    for (int k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);
    struct Poly { int s; unsigned a; std::array<unsigned, 3> m; };
    const Poly polys[3] = {{1, 0, {1, 0, 0}}, {2, 1, {1, 3, 0}}, {3, 1, {1, 3, 1}}};
    for (int d = 1; d < 4; ++d) {
      const Poly& p = polys[d - 1];
      auto& V = v[d];
      for (int k = 0; k < p.s; ++k) V[k] = p.m[k] << (31 - k);
      for (int k = p.s; k < 32; ++k) {
        V[k] = V[k - p.s] ^ (V[k - p.s] >> p.s);
        for (int j = 1; j < p.s; ++j)
          if ((p.a >> (p.s - 1 - j)) & 1u) V[k] ^= V[k - j];
      }
    }
  }
};
const SobolMatrices kSobol;

std::uint32_t reverse_bits(std::uint32_t x) {
  x = __builtin_bswap32(x);  // bytes; then nibbles, pairs and bits within each byte
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

// Dimensions 1-3 of Sobol index i, bit-reversed, by bytes of i: entry [b][v] is the
// XOR of the reversed direction numbers of the bits set in byte b = v (4 lookups
// instead of one step per set bit of a 32-bit shuffled index).
struct SobolByteTables {
  struct Entry {
    std::uint32_t d[3];
  };
  std::array<std::array<Entry, 256>, 4> t{};
  explicit SobolByteTables(const SobolMatrices& m) {
    for (int b = 0; b < 4; ++b)
      for (unsigned v = 0; v < 256; ++v)
        for (int k = 0; k < 8; ++k)
          if ((v >> k) & 1u)
            for (int d = 0; d < 3; ++d) t[b][v].d[d] ^= reverse_bits(m.v[d + 1][8 * b + k]);
  }
};
const SobolByteTables kSobolBytes(kSobol);

// Burley 2020 eq. (listing 2): a hash that only lets lower bits affect higher ones,
// so applied to bit-reversed values it is a nested uniform (Owen) scramble.
std::uint32_t laine_karras_permutation(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

}  // namespace

const char* to_string(SamplerKind k) { return k == SamplerKind::Sobol ? "sobol" : "independent"; }

SamplerKind parse_sampler_kind(const std::string& s) {
  for (SamplerKind k : kSamplerKinds)
    if (s == to_string(k)) return k;
  throw Error("unknown sampler '" + s + "': use 'sobol' or 'independent'");
}

std::uint32_t nested_uniform_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

std::uint32_t sobol(std::uint32_t i, int d) {
  if (d == 0) return reverse_bits(i);  // van der Corput
  std::uint32_t x = 0;
  for (; i; i &= i - 1) x ^= kSobol.v[d][std::countr_zero(i)];
  return x;
}

std::uint32_t hash_combine(std::uint32_t a, std::uint32_t b) {
  // murmur3-style finaliser over the pair.
  std::uint32_t h = a * 0x9e3779b9u ^ (b + 0x7f4a7c15u + (a << 6) + (a >> 2));
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return h;
}

void PixelSampler::start(int x, int y, std::uint32_t index) {
  pixel_seed_ = hash_combine(hash_combine(seed_, std::uint32_t(x)), std::uint32_t(y));
  index_ = index;
  reversed_index_ = reverse_bits(index);
  pattern_ = 0;
}

// Burley 2020 §4: shuffle the index, then Owen-scramble each dimension with its own
// seed: dimension d is nested_uniform_scramble(sobol(i, d), hash_combine(seed, d + 1))
// with i = nested_uniform_scramble(index, seed), the pattern's seed. Written with
// the bit reversals that cancel left out: nested_uniform_scramble(x) reverses x,
// and dimension 0 is reverse_bits(i), dimensions 1-3 come reversed from the tables.
template <int D>
void PixelSampler::draw(float* out) {
  const std::uint32_t pattern_seed = hash_combine(pixel_seed_, pattern_++);
  if (kind_ == SamplerKind::Sobol) {
    const std::uint32_t i = reverse_bits(laine_karras_permutation(reversed_index_, pattern_seed));
    std::uint32_t rx[4] = {i, 0, 0, 0};  // dimension d of index i, bit-reversed
    for (int b = 0; b < 4; ++b) {
      const auto& e = kSobolBytes.t[b][(i >> (8 * b)) & 0xffu];
      for (int d = 1; d < D; ++d) rx[d] ^= e.d[d - 1];
    }
    for (int d = 0; d < D; ++d)
      out[d] = to_unit(reverse_bits(laine_karras_permutation(rx[d], hash_combine(pattern_seed, std::uint32_t(d) + 1))));
  } else {
    const std::uint32_t s = hash_combine(pattern_seed, index_);
    for (int d = 0; d < D; ++d) out[d] = to_unit(hash_combine(s, std::uint32_t(d) + 0x51ed27u));
  }
}

glm::vec4 PixelSampler::next4() {
  float u[4];
  draw<4>(u);
  return {u[0], u[1], u[2], u[3]};
}

glm::vec2 PixelSampler::next2() {
  float u[2];
  draw<2>(u);
  return {u[0], u[1]};
}

}  // namespace plumage
