#pragma once
// The command line's one validation layer. Every number and every named value a
// flag takes passes a CLI11 validator here, so a bad value is a usage error
// (exit 2, one line naming the flag) before any file is read or written.
// check_option_types() gives every floating-point option the finiteness check
// and every unsigned one the sign check, so a new option cannot forget them;
// commands add ranges, choices and sizes where they declare their options.
#include <cerrno>
#include <cfloat>
#include <climits>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <cstdlib>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

#include "plumage/renderer/dome_rig.h"

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

// A whole number a 64-bit unsigned integer holds: "-1" would otherwise wrap to
// 2^64-1, and 2^64 or more would saturate (--seed 18446744073709551616 rendering
// another seed's image).
inline CLI::Validator unsigned_integer() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto first = text.find_first_not_of(" \t");
        if (first != std::string::npos && text[first] == '-') return "'" + text + "' is negative; give 0 or more";
        if (first == std::string::npos || text.find_first_not_of("0123456789", first) != std::string::npos)
          return "'" + text + "' is not a whole number";
        errno = 0;
        (void)std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE) return "'" + text + "' is above 18446744073709551615, the largest value";
        return {};
      },
      "", "UINT64");
}

// A whole number an int holds (signed, 32-bit); CLI11 would refuse a larger one
// with a conversion message that does not say why.
inline CLI::Validator whole_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto first = text.find_first_not_of(" \t");
        const auto digits = first != std::string::npos && (text[first] == '-' || text[first] == '+') ? first + 1 : first;
        if (digits == std::string::npos || digits >= text.size() ||
            text.find_first_not_of("0123456789", digits) != std::string::npos)
          return "'" + text + "' is not a whole number";
        errno = 0;
        const long long v = std::strtoll(text.c_str(), nullptr, 10);
        if (errno == ERANGE || v > INT_MAX || v < INT_MIN) return "'" + text + "' is beyond the range of whole numbers this option takes";
        return {};
      },
      "", "INT");
}

// Dome LEDs: all, none, or LED numbers and ranges (1,5,12 or 2-9); the grammar of
// light_ranges (renderer/dome_rig.h). Whether each LED exists is known once the
// rig is read.
inline CLI::Validator light_list() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          (void)light_ranges(text);
        } catch (const std::exception& e) {
          std::string why = e.what();
          if (why.rfind("--lights: ", 0) == 0) why = why.substr(10);
          return why;
        }
        return {};
      },
      "", "LEDS");
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

// A comma-separated list whose every item passes `item` ("hair,substructure").
inline CLI::Validator comma_list(CLI::Validator item) {
  return CLI::Validator(
      [item](std::string& text) -> std::string {
        if (text.empty() || text.back() == ',') return "'" + text + "' has an empty item";
        std::stringstream items(text);
        for (std::string one; std::getline(items, one, ',');)
          if (std::string why = item(one); !why.empty()) return why;
        return {};
      },
      "", "LIST");
}

// A comma-separated list of whole numbers in [lo, hi] ("1,2,4,8").
inline CLI::Validator whole_number_list(int lo, int hi) {
  const CLI::Validator range = in_range(lo, hi);
  return comma_list(CLI::Validator(
      [range](std::string& text) -> std::string {
        if (text.empty() || text.size() > 10 || text.find_first_not_of("0123456789") != std::string::npos)
          return "'" + text + "' is not a whole number";
        return range(text);
      },
      "", "WHOLE"));
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

// --tile I/N: part I (1-based) of N, 1 <= I <= N <= kMaxTiles. Parsed into
// 0-based index and count; false when the text is not of that form.
inline constexpr int kMaxTiles = 4096;
inline bool parse_tile(const std::string& text, int& index, int& count) {
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) return false;
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  if (a.find_first_not_of("0123456789") != std::string::npos || b.find_first_not_of("0123456789") != std::string::npos ||
      a.size() > 5 || b.size() > 5)
    return false;
  const int i = std::stoi(a), n = std::stoi(b);
  if (!(i >= 1 && n >= 1 && i <= n && n <= kMaxTiles)) return false;
  index = i - 1;
  count = n;
  return true;
}
inline CLI::Validator tile_part() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        int i = 0, n = 0;
        return parse_tile(text, i, n) ? std::string()
                                      : "'" + text + "' is not I/N with 1 <= I <= N <= " + std::to_string(kMaxTiles) + " (e.g. 2/8)";
      },
      "I/N", "TILE");
}

// An output image named by -o: its extension picks the format, one of `exts`.
// The message of a usage error, or "" when the name is fine.
inline std::string image_output_problem(const std::string& output, std::initializer_list<const char*> exts) {
  std::string list;
  for (const char* e : exts) list += (list.empty() ? "" : ", ") + std::string(e);
  if (output.empty()) return "-o is empty: give a file name such as out.png";
  const std::string ext = std::filesystem::path(output).extension().string();
  for (const char* e : exts)
    if (ext == e) return {};
  return "-o " + output + ": the extension picks the format; end the name with one of " + list +
         " (.exr linear, .png sRGB)";
}

// Gives every floating-point option of `app` and its subcommands finite_number(),
// every unsigned integer option unsigned_integer() and every signed one
// whole_number() (every INT option of plumage is an int).
inline void check_option_types(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) {
    const std::string type = opt->get_type_name();
    if (type == "FLOAT") opt->check(finite_number());
    else if (type == "UINT") opt->check(unsigned_integer());
    else if (type == "INT") opt->check(whole_number());
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) check_option_types(*sub);
}

}  // namespace plumage::cli
