// The project's JSON inputs read one way (json_reader.h).
#include "plumage/common/json_reader.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/error.h"
#include "plumage/common/number_text.h"

namespace plumage {
namespace {

// "[lo, hi]", ">= lo" or "<= hi", the ends as a person reads them.
std::string allowed(double lo, double hi) {
  std::string text = std::isinf(hi) ? ">= " : std::isinf(lo) ? "<= " : "[";
  text += std::isinf(hi) ? num(lo) : std::isinf(lo) ? num(hi) : num(lo) + ", " + num(hi) + "]";
  return text;
}

}  // namespace

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> d(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) d[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t prev = d[0];
    d[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cur = d[j];
      d[j] = std::min({d[j] + 1, d[j - 1] + 1, prev + (a[i - 1] != b[j - 1])});
      prev = cur;
    }
  }
  return d[b.size()];
}

JsonReader::JsonReader(const nlohmann::json& top, std::string file, std::string hint)
    : JsonReader(top, std::make_shared<const std::string>(std::move(file)),
                 std::make_shared<const std::string>(std::move(hint)), std::string()) {}

JsonReader::JsonReader(const nlohmann::json& j, std::shared_ptr<const std::string> file,
                       std::shared_ptr<const std::string> hint, std::string place)
    : j_(&j), file_(std::move(file)), hint_(std::move(hint)), place_(std::move(place)),
      known_(j.is_object() ? std::make_shared<std::set<std::string>>() : nullptr) {}

JsonReader JsonReader::child(const nlohmann::json& j, std::string place) const {
  return JsonReader(j, file_, hint_, std::move(place));
}

void JsonReader::fail(const std::string& what) const {
  throw Error(Location{*file_}, (place_.empty() ? std::string("top level") : place_) + ": " + what +
                                    (hint_->empty() ? std::string() : " (" + *hint_ + ")"));
}

void JsonReader::expect_object() const {
  if (!j_->is_object()) fail(std::string("expected an object {...}, got ") + j_->type_name());
}

bool JsonReader::has(const std::string& key) const {
  expect_object();
  known_->insert(key);
  return j_->contains(key);
}

std::optional<JsonReader> JsonReader::find(const std::string& key) const {
  expect_object();
  known_->insert(key);
  const auto it = j_->find(key);
  if (it == j_->end()) return std::nullopt;
  return child(*it, place_.empty() ? key : place_ + "." + key);
}

JsonReader JsonReader::member(const std::string& key) const {
  std::optional<JsonReader> m = find(key);
  if (!m) fail("missing key \"" + key + "\"");
  return *m;
}

void JsonReader::finish() const {
  if (!j_->is_object()) return;
  for (auto it = j_->begin(); it != j_->end(); ++it) {
    if (known_->count(it.key())) continue;
    std::string best;
    std::size_t best_d = 4;
    std::string known;
    for (const std::string& k : *known_) {
      const std::size_t d = edit_distance(it.key(), k);
      if (d < best_d) best_d = d, best = k;
      known += (known.empty() ? "" : ", ") + k;
    }
    child(it.value(), place_.empty() ? it.key() : place_ + "." + it.key())
        .fail("unknown key" + (best.empty() ? std::string() : " (did you mean '" + best + "'?)") +
              "; known keys here: " + known);
  }
}

std::vector<JsonReader> JsonReader::elements(std::size_t count, std::size_t min_count, std::size_t max_count) const {
  if (!j_->is_array()) fail(std::string("expected an array [...], got ") + j_->type_name());
  const std::size_t n = j_->size();
  const auto values = [](std::size_t k) { return std::to_string(k) + (k == 1 ? " value" : " values"); };
  if (count != 0 && n != count) fail("expected " + values(count) + ", got " + std::to_string(n));
  if (n < min_count) fail("expected at least " + values(min_count) + ", got " + std::to_string(n));
  if (n > max_count) fail("expected at most " + values(max_count) + ", got " + std::to_string(n));
  std::vector<JsonReader> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(child((*j_)[i], place_ + "[" + std::to_string(i) + "]"));
  return out;
}

double JsonReader::number(double lo, double hi) const {
  if (!j_->is_number()) fail(std::string("expected a number, got ") + j_->type_name());
  const double v = j_->get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) fail("value " + num(v) + " is out of range; allowed " + allowed(lo, hi));
  return v;
}

long long JsonReader::integer(long long lo, long long hi) const {
  const bool whole = j_->is_number_integer() || (j_->is_number_float() && std::isfinite(j_->get<double>()) &&
                                                 std::floor(j_->get<double>()) == j_->get<double>());
  if (!whole) fail("expected an integer, got " + (j_->is_number() ? j_->dump() : std::string(j_->type_name())));
  const double v = j_->get<double>();
  if (v < double(lo) || v > double(hi))
    fail("value " + j_->dump() + " is out of range; allowed integers " + allowed(double(lo), double(hi)));
  return j_->is_number_unsigned() ? (long long)(j_->get<unsigned long long>()) : j_->get<long long>();
}

bool JsonReader::boolean() const {
  if (!j_->is_boolean()) fail(std::string("expected true or false, got ") + j_->type_name());
  return j_->get<bool>();
}

std::string JsonReader::string() const {
  if (!j_->is_string()) fail(std::string("expected a string, got ") + j_->type_name());
  return j_->get<std::string>();
}

std::vector<double> JsonReader::numbers(std::size_t count, double lo, double hi) const {
  if (!j_->is_array()) fail(std::string("expected an array [...], got ") + j_->type_name());
  if (count != 0 && j_->size() != count) elements(count);  // fails, naming the count
  std::vector<double> out;
  out.reserve(j_->size());
  for (std::size_t i = 0; i < j_->size(); ++i) {
    const nlohmann::json& e = (*j_)[i];
    const double v = e.is_number() ? e.get<double>() : 0.0;
    // A place is written out only for an element that fails (number() says why).
    if (!e.is_number() || !std::isfinite(v) || v < lo || v > hi) child(e, place_ + "[" + std::to_string(i) + "]").number(lo, hi);
    out.push_back(v);
  }
  return out;
}

}  // namespace plumage
