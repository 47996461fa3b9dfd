#pragma once
// Whether every component of a GLM vector or matrix is finite (neither NaN nor
// ±Inf): the one check input validation, the BCSDF's guards and the filters share.
// An Image's pixels: all_finite(const Image&), image.h.
#include <cmath>

#include <glm/glm.hpp>

namespace plumage {

template <glm::length_t N, typename T, glm::qualifier Q>
inline bool all_finite(const glm::vec<N, T, Q>& v) {
  for (glm::length_t i = 0; i < N; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

template <glm::length_t C, glm::length_t R, typename T, glm::qualifier Q>
inline bool all_finite(const glm::mat<C, R, T, Q>& m) {
  for (glm::length_t c = 0; c < C; ++c)
    if (!all_finite(m[c])) return false;
  return true;
}

}  // namespace plumage
