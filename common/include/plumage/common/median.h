#pragma once
// The median of a list as the project takes it everywhere: the element that
// would stand at index size / 2 once sorted (the upper of the two middle ones
// for an even count), found by std::nth_element on a copy.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace plumage {

// `if_empty` for an empty list.
template <class T>
T median(std::vector<T> v, T if_empty = T()) {
  if (v.empty()) return if_empty;
  const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The spread of a list about `centre` as a Gaussian's sigma: 1.4826 times the
// median absolute deviation (MAD), robust to the few values far from the rest.
template <class T>
double mad_sigma(std::vector<T> v, T centre = T()) {
  for (T& x : v) x = T(std::fabs(x - centre));
  return 1.4826 * median(std::move(v));
}

}  // namespace plumage
