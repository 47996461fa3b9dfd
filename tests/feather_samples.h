#pragma once
// Feathers for tests and benchmarks of the curve formats: a plausible one of a
// chosen size, and random ones with extreme but valid values.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>

#include "plumage/common/feather.h"

namespace plumage::samples {

// A flat feather: shaft along +Y, `barbs` barbs alternating left/right, each
// with `points_per_barb` control points, vane normals tilted a little off +Z.
inline Feather sample_feather(int barbs, int points_per_barb, std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f);
  Feather f;
  f.provenance.source = "test:sample";
  f.provenance.seed = seed;
  f.albedo.color = {0.42f, 0.31f, 0.2f};
  f.left = {30, 0.02f, 0.004f, 40.0f, 12.0f, 0.25f, 0.35f};
  f.right = {28, 0.021f, 0.0041f, 42.5f, -8.0f, 0.3f, 0.33f};
  const float length = 60.0f;
  Curve shaft;
  shaft.kind = CurveKind::Shaft;
  for (int i = 0; i < 12; ++i) {
    const float t = float(i) / 11.0f;
    shaft.points.push_back({{0.3f * t * t, length * t, 0.5f * t}, 0.6f * (1.0f - 0.8f * t), {0, 0, 1}});
  }
  f.curves.push_back(shaft);
  for (int b = 0; b < barbs; ++b) {
    Curve c;
    c.side = b % 2 ? VaneSide::Right : VaneSide::Left;
    c.root = float(b / 2) / float(std::max(1, barbs / 2));
    const float sign = c.side == VaneSide::Right ? 1.0f : -1.0f;
    const float y0 = c.root * length, len = 25.0f * (1.0f - 0.6f * c.root) + 2.0f;
    for (int i = 0; i < points_per_barb; ++i) {
      const float s = float(i) / float(points_per_barb - 1);
      glm::vec3 n = glm::normalize(glm::vec3(jitter(rng), jitter(rng), 1.0f));
      c.points.push_back({{sign * len * s * 0.8f, y0 + len * s * 0.6f, 0.8f * s * s + jitter(rng)},
                          0.05f * (1.0f - 0.7f * s),
                          n});
    }
    f.curves.push_back(std::move(c));
  }
  return f;
}

// A finite float from random bits: every exponent (denormals, 1e-38, 1e38) is as
// likely as every other, and some picks are the awkward values by name.
inline float extreme_float(std::mt19937_64& rng) {
  static const float named[] = {0.0f,
                                -0.0f,
                                1e30f,
                                -1e30f,
                                std::numeric_limits<float>::denorm_min(),
                                -std::numeric_limits<float>::denorm_min(),
                                std::numeric_limits<float>::min(),
                                std::numeric_limits<float>::max(),
                                -std::numeric_limits<float>::max(),
                                1.0f,
                                0.1f,
                                1.0f / 3.0f,
                                16777217.0f};
  if (rng() % 4 == 0) return named[rng() % std::size(named)];
  for (;;) {
    const float v = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    if (std::isfinite(v)) return v;
  }
}

inline float extreme_nonneg(std::mt19937_64& rng) {
  const float v = extreme_float(rng);
  return std::signbit(v) && v != 0.0f ? -v : v;  // keeps -0.0, which is not negative
}

inline float unit_interval(std::mt19937_64& rng) {
  static const float named[] = {0.0f, -0.0f, 1.0f, std::numeric_limits<float>::denorm_min(),
                                std::nextafter(1.0f, 0.0f)};
  if (rng() % 4 == 0) return named[rng() % std::size(named)];
  return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
}

inline glm::vec3 random_unit(std::mt19937_64& rng) {
  switch (rng() % 4) {
    case 0:
      return {-0.0f, 0.0f, 1.0f};
    case 1:
      return {1.0f, std::numeric_limits<float>::denorm_min(), -0.0f};
    default:
      break;
  }
  std::normal_distribution<float> g;
  for (;;) {
    const glm::vec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

// Printable text including the characters the format must quote or escape.
inline std::string random_text(std::mt19937_64& rng) {
  static const char* pieces[] = {
      "a", "Z", " ", "\"", "\\", "#", "preset:", "photo:", ".png", "é", "鳥", "\\\"", "'"};
  std::string s;
  const int n = int(rng() % 8);
  for (int i = 0; i < n; ++i) s += pieces[rng() % std::size(pieces)];
  return s;
}

// A random feather that the format must carry exactly.
inline Feather random_feather(std::mt19937_64& rng) {
  Feather f;
  f.provenance.source = random_text(rng);
  if (rng() % 2) f.provenance.seed = rng() % 3 == 0 ? std::numeric_limits<std::uint64_t>::max() : rng();
  f.albedo.color = {extreme_nonneg(rng), extreme_nonneg(rng), extreme_nonneg(rng)};
  if (rng() % 2) {
    f.albedo.texture = random_text(rng) + "x";
    float a = extreme_float(rng), b = extreme_float(rng);
    if (a == b) a = -1.0f, b = 1.0f;
    f.albedo.rect_min = {std::min(a, b), std::min(a, b)};
    f.albedo.rect_max = {std::max(a, b), std::max(a, b)};
  }
  if (rng() % 2) f.albedo.scale = 1.0f + 7.0f * unit_interval(rng);  // paler than the paper: [1, 8]
  if (rng() % 2)  // one colour, or several along the shaft
    for (std::size_t k = 0, n = 1 + rng() % 4; k < n; ++k)
      f.albedo.shaft.push_back(glm::vec3(extreme_nonneg(rng), extreme_nonneg(rng), extreme_nonneg(rng)));
  if (rng() % 2) {  // a medulla: ratio in [0, 1), coefficients anywhere >= 0
    f.medulla.ratio = std::min(unit_interval(rng), std::nextafter(1.0f, 0.0f));
    f.medulla.sigma_s = {extreme_nonneg(rng), extreme_nonneg(rng), extreme_nonneg(rng)};
    f.medulla.sigma_a = {extreme_nonneg(rng), extreme_nonneg(rng), extreme_nonneg(rng)};
    if (!(f.medulla.ratio > 0)) f.medulla = Medulla{};  // ratio 0 is written as no record
  }
  for (SubstructureParams* p : {&f.left, &f.right}) {
    // Anywhere in the ranges every stage accepts (substructure_problem), ends included.
    p->barbules_per_side = int(rng() % 1000);
    p->ribbon_width = 10.0f * unit_interval(rng);
    p->ramus_radius = 0.5f * p->ribbon_width * unit_interval(rng);
    p->barbule_radius = unit_interval(rng);
    p->elevation_deg = 1.0f + 89.0f * unit_interval(rng);
    p->azimuth_deg = std::nextafter(90.0f, 0.0f) * (2.0f * unit_interval(rng) - 1.0f);
    p->hooked_fraction = unit_interval(rng);
  }
  if (rng() % 2) f.down_cover = std::max(unit_interval(rng), std::nextafter(0.0f, 1.0f));  // (0, 1]
  const bool shaft = rng() % 4 != 0;
  const int barbs = int(rng() % 12);
  for (int i = 0; i < int(shaft) + barbs; ++i) {
    Curve c;
    if (shaft && i == 0) {
      c.kind = CurveKind::Shaft;
    } else {
      c.side = rng() % 2 ? VaneSide::Left : VaneSide::Right;
      if (rng() % 4 == 0) c.kind = CurveKind::Down;
    }
    c.root = unit_interval(rng);
    const int n = 4 + int(rng() % 9);
    for (int k = 0; k < n; ++k)
      c.points.push_back({{extreme_float(rng), extreme_float(rng), extreme_float(rng)},
                          extreme_nonneg(rng),
                          random_unit(rng)});
    f.curves.push_back(std::move(c));
  }
  return f;
}

}  // namespace plumage::samples
