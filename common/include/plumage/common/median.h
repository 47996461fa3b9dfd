#pragma once
// The median of a list as the project takes it everywhere: the element that
// would stand at index size / 2 once sorted (the upper of the two middle ones
// for an even count), found by std::nth_element on a copy.
#include <algorithm>
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

}  // namespace plumage
