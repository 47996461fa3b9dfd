#pragma once
// Numbers as text for the writers in common/: floats in the shortest form that
// reads back to the same float (std::to_chars' guarantee), integers exactly.
#include <charconv>
#include <string>

namespace plumage::detail {

inline void append_float(std::string& out, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

template <class Int>
inline void append_int(std::string& out, Int v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

}  // namespace plumage::detail
