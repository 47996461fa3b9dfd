#pragma once
// A number as a person reads it in a message or a report: six significant
// digits, no trailing zeros ("0.1", "32.9615", "1e-07"), as an iostream writes
// a double by default. Files that must read back exactly use the shortest
// round-trip form instead (common/src/float_text.h).
#include <sstream>
#include <string>

namespace plumage {

inline std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace plumage
