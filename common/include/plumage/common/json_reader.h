#pragma once
// Reading the project's JSON inputs — layout.json, feather parameter files, light
// rigs — one way (docs/robustness.md, "Malformed input"). A JsonReader is a value of
// a parsed file together with where it is, written as a person reads it
// ("feathers[0].vanes.left.width_mm"; the top is "top level"), so every error names
// the file, the place and what was wrong, in one line:
//   FILE: shaft.length: expected a number, got boolean
// plus the format's own pointer to its documentation where it gives one. A reader
// of an object remembers the keys it was asked for, so a strict format can refuse
// the keys left over (finish(): "unknown key (did you mean 'length'?); known keys
// here: ..."), and a lenient one simply never calls it.
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace plumage {

class JsonReader {
 public:
  // The whole file `file` (already parsed; parse_json in json_file.h). `hint`, when
  // not empty, ends every error in parentheses ("see docs/layout-format.md").
  JsonReader(const nlohmann::json& top, std::string file, std::string hint = {});

  const nlohmann::json& value() const { return *j_; }
  // "feathers[0].vanes.left", "" for the top.
  const std::string& place() const { return place_; }
  // Throws plumage::Error at the file: "PLACE: what (hint)".
  [[noreturn]] void fail(const std::string& what) const;

  // --- objects (each fails "expected an object {...}, got TYPE" on anything else)
  void expect_object() const;
  // The member `key`, or nothing when there is none; either way `key` is known.
  std::optional<JsonReader> find(const std::string& key) const;
  // The member `key`; fails "missing key" when there is none.
  JsonReader member(const std::string& key) const;
  bool has(const std::string& key) const;
  // Fails on the first key not asked for through find, member or has, naming the
  // nearest known one (at most three edits away) and all of them.
  void finish() const;

  // --- arrays (each fails "expected an array ..." on anything else)
  // The elements, `count` of them when not 0 ("expected N values, got M"), at least
  // `min_count`, at most `max_count`.
  std::vector<JsonReader> elements(std::size_t count = 0, std::size_t min_count = 0,
                                   std::size_t max_count = std::numeric_limits<std::size_t>::max()) const;

  // --- scalars
  // A number within [lo, hi] ("value V is out of range; allowed [lo, hi]").
  double number(double lo = -std::numeric_limits<double>::infinity(),
                double hi = std::numeric_limits<double>::infinity()) const;
  // A whole number (1 and 1.0 alike) within [lo, hi].
  long long integer(long long lo, long long hi) const;
  bool boolean() const;
  std::string string() const;
  // An array of numbers, each within [lo, hi], `count` of them when not 0.
  std::vector<double> numbers(std::size_t count = 0, double lo = -std::numeric_limits<double>::infinity(),
                              double hi = std::numeric_limits<double>::infinity()) const;

 private:
  JsonReader(const nlohmann::json& j, std::shared_ptr<const std::string> file, std::shared_ptr<const std::string> hint,
             std::string place);
  JsonReader child(const nlohmann::json& j, std::string place) const;

  const nlohmann::json* j_;
  std::shared_ptr<const std::string> file_, hint_;
  std::string place_;
  std::shared_ptr<std::set<std::string>> known_;  // keys asked for (objects only; shared by copies)
};

// The Levenshtein distance between two strings (insertions, deletions, substitutions).
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace plumage
