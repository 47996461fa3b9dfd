#pragma once
// Numbers as text for the writers in common/: floats in the shortest form that
// reads back to the same float (std::to_chars' guarantee), integers exactly.
#include <charconv>
#include <string>

#include <glm/vec3.hpp>

namespace plumage::detail {

inline void append_float(std::string& out, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

// "x y z": a vector's components separated by single spaces.
inline void append_vec3(std::string& out, const glm::vec3& v) {
  append_float(out, v.x);
  out += ' ';
  append_float(out, v.y);
  out += ' ';
  append_float(out, v.z);
}

template <class Int>
inline void append_int(std::string& out, Int v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

}  // namespace plumage::detail
