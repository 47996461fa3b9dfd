#pragma once
// A float atan2 for estimates (the light-pick weights of next-event estimation),
// where a few 1e-6 of error choose lights a little differently and bias nothing.
#include <algorithm>
#include <cmath>

namespace plumage {

// atan2 within 1e-5 rad: octant reduction and a minimax polynomial for atan on
// [0, 1] (Abramowitz & Stegun 4.4.49 form, |error| <= 1e-5); 0 at the origin.
inline float atan2_approx(float y, float x) {
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float mx = std::max(ax, ay), mn = std::min(ax, ay);
  const float a = mn / std::max(mx, 1e-30f), s = a * a;
  float r = ((((0.0208351f * s - 0.0851330f) * s + 0.1801410f) * s - 0.3302995f) * s + 0.9998660f) * a;
  r = ay > ax ? 1.57079637f - r : r;
  r = x < 0.0f ? 3.14159274f - r : r;
  return y < 0.0f ? -r : r;
}

}  // namespace plumage
