#pragma once
// The command line's one validation layer. Every number and every named value a
// flag takes passes a CLI11 validator here, so a bad value is a usage error
// (exit 2, one line naming the flag) before any file is read or written.
// check_option_types() gives every floating-point option the finiteness check
// and every unsigned one the sign check, so a new option cannot forget them;
// commands add ranges, choices and sizes where they declare their options.
#include <cfloat>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

namespace plumage::cli {

namespace detail {
// Parses the whole of `text` as a number; false for trailing junk or none.
inline bool parse_double(const std::string& text, double& v) {
  if (text.empty()) return false;
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

inline std::string short_number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}
}  // namespace detail

// A number a float can hold: NaN, Inf and magnitudes above FLT_MAX are refused.
inline CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (!detail::parse_double(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v) || std::fabs(v) > FLT_MAX) return "'" + text + "' is not a finite number";
        return {};
      },
      "", "FINITE");
}

// A finite number in [lo, hi] (ends included); `lo_open` excludes lo.
inline CLI::Validator in_range(double lo, double hi, bool lo_open = false) {
  const std::string range = std::string(lo_open ? "(" : "[") + detail::short_number(lo) + ", " +
                            detail::short_number(hi) + "]";
  return CLI::Validator(
      [lo, hi, lo_open, range](std::string& text) -> std::string {
        double v = 0;
        if (!detail::parse_double(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v)) return "'" + text + "' is not a finite number";
        if (v < lo || v > hi || (lo_open && v == lo)) return "'" + text + "' is outside " + range;
        return {};
      },
      range, "RANGE");
}

// A finite number above zero (and at most `hi`).
inline CLI::Validator positive(double hi = FLT_MAX) { return in_range(0.0, hi, true); }

// A whole number of at least zero: "-1" would otherwise wrap to 2^64-1.
inline CLI::Validator non_negative_integer() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto first = text.find_first_not_of(" \t");
        if (first != std::string::npos && text[first] == '-') return "'" + text + "' is negative; give 0 or more";
        return {};
      },
      "", "NONNEGATIVE");
}

// A comma-separated list of finite numbers (each at least `min`) whose length is
// one of `counts`: "X,Y,Z" points and vectors, "DX,DY,DZ,E" lights.
inline CLI::Validator number_list(std::vector<std::size_t> counts, double min = -FLT_MAX) {
  std::string want;
  for (std::size_t n : counts) want += (want.empty() ? "" : " or ") + std::to_string(n);
  return CLI::Validator(
      [counts, min, want](std::string& text) -> std::string {
        std::size_t n = 0;
        std::stringstream items(text);
        for (std::string item; std::getline(items, item, ',');) {
          double v = 0;
          if (!detail::parse_double(item, v) || !std::isfinite(v) || std::fabs(v) > FLT_MAX)
            return "'" + item + "' is not a finite number";
          if (v < min) return "'" + item + "' is below " + detail::short_number(min);
          ++n;
        }
        if (!text.empty() && text.back() == ',') n = 0;  // "1,2," has an empty last item
        if (std::find(counts.begin(), counts.end(), n) == counts.end())
          return "'" + text + "': give " + want + " comma-separated numbers";
        return {};
      },
      "", "NUMBERS");
}

// One of the named values.
inline CLI::Validator one_of(std::vector<std::string> names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return CLI::Validator(
      [names, list](std::string& text) -> std::string {
        for (const auto& n : names)
          if (text == n) return {};
        return "'" + text + "' is not one of: " + list;
      },
      "{" + list + "}", "CHOICE");
}

// One of a library enum's values, named by its to_string: the choices are listed
// once, beside the enum (kShadingModes, kLightPicks, ...), and the library's parser
// takes exactly these names.
template <class E, std::size_t N>
  requires std::is_enum_v<E>
CLI::Validator one_of(const E (&values)[N]) {
  std::vector<std::string> names;
  for (E v : values) names.push_back(to_string(v));
  return one_of(std::move(names));
}

// The largest image a command renders: 16384 pixels a side and 64 megapixels,
// whose film (accumulated radiance, variance and sample counts) needs about
// 3 GiB. A larger --resolution is refused before anything is allocated.
inline constexpr int kMaxImageSide = 16384;
inline constexpr double kMaxRenderMegapixels = 64.0;

// Ceilings of the sampling options: beyond them a render would not end in a
// day, or the thread pool would not start.
inline constexpr int kMaxSpp = 1 << 20;
inline constexpr int kMaxThreads = 4096;

// Parses "WIDTHxHEIGHT"; false when it is not two positive integers.
inline bool parse_resolution(const std::string& text, int& width, int& height) {
  const auto x = text.find('x');
  if (x == std::string::npos || x == 0 || x + 1 >= text.size()) return false;
  for (std::size_t i = 0; i < text.size(); ++i)
    if (i != x && (text[i] < '0' || text[i] > '9')) return false;
  if (x > 9 || text.size() - x - 1 > 9) return false;  // more digits than an int holds
  width = std::stoi(text.substr(0, x));
  height = std::stoi(text.substr(x + 1));
  return width > 0 && height > 0;
}

// "WIDTHxHEIGHT" within kMaxImageSide and kMaxRenderMegapixels.
inline CLI::Validator resolution() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        int w = 0, h = 0;
        if (!parse_resolution(text, w, h)) return "'" + text + "': give WIDTHxHEIGHT, two whole numbers above 0, e.g. 640x480";
        const double mp = double(w) * h / 1e6;
        if (w > kMaxImageSide || h > kMaxImageSide || mp > kMaxRenderMegapixels)
          return "'" + text + "' is " + detail::short_number(mp) + " megapixels; the limit is " +
                 std::to_string(kMaxImageSide) + " pixels a side and " + detail::short_number(kMaxRenderMegapixels) +
                 " megapixels";
        return {};
      },
      "WIDTHxHEIGHT", "RESOLUTION");
}

// Gives every floating-point option of `app` and its subcommands finite_number()
// and every unsigned integer option non_negative_integer().
inline void check_option_types(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) {
    const std::string type = opt->get_type_name();
    if (type == "FLOAT") opt->check(finite_number());
    else if (type == "UINT") opt->check(non_negative_integer());
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) check_option_types(*sub);
}

}  // namespace plumage::cli
