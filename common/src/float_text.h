#pragma once
// Numbers and strings as text for the writers in common/: floats in the shortest
// form that reads back to the same float (std::to_chars' guarantee), integers
// exactly, strings in double quotes as line_reader.h reads them.
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

// No control character (newline, tab, ...): fits in one line of a text format.
inline bool printable_string(const std::string& s) {
  for (unsigned char c : s)
    if (c < 0x20 || c == 0x7f) return false;
  return true;
}

// "s" with \" and \\ escaped.
inline void append_quoted(std::string& out, const std::string& s) {
  out += '"';
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  out += '"';
}

}  // namespace plumage::detail
