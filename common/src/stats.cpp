#include "plumage/common/stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <vector>

namespace plumage {
namespace {
struct Registry {
  std::mutex mu;
  std::vector<StatCounter*> counters;
  std::map<std::string, double> values;
};
Registry& registry() {
  static Registry r;
  return r;
}
}  // namespace

StatCounter::StatCounter(const char* name) : name_(name) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  r.counters.push_back(this);
}

// Counters are usually static, but a counter with a shorter life (a test's, a
// plugin's) must not leave a dangling pointer behind.
StatCounter::~StatCounter() {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  std::erase(r.counters, this);
}

void stats_set_value(const std::string& name, double value) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  r.values[name] = value;
}

double stats_add_value(const std::string& name, double value) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  return r.values[name] += value;
}

std::map<std::string, double> stats_snapshot() {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  std::map<std::string, double> out = r.values;
  for (const StatCounter* c : r.counters) out[c->name()] += double(c->value());
  return out;
}

void stats_reset() {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  for (StatCounter* c : r.counters) c->reset();
  r.values.clear();
}

namespace {
std::string format_stat(double value) {
  char buf[64];
  if (value == double(static_cast<long long>(value)) && std::abs(value) < 1e15)
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(value));
  else
    std::snprintf(buf, sizeof buf, "%.6g", value);
  return buf;
}
}  // namespace

void stats_print(std::ostream& os) {
  struct Row {
    std::string category, item, value;
  };
  std::vector<Row> rows;
  std::size_t item_width = 0, value_width = 0;
  for (const auto& [name, value] : stats_snapshot()) {
    const auto slash = name.find('/');
    Row row{slash == std::string::npos ? "" : name.substr(0, slash),
            slash == std::string::npos ? name : name.substr(slash + 1), format_stat(value)};
    item_width = std::max(item_width, row.item.size());
    value_width = std::max(value_width, row.value.size());
    rows.push_back(std::move(row));
  }
  // Every counter, zeros included (a NaN count of 0 is worth seeing); names
  // left-aligned and values right-aligned, each in one column.
  os << "Statistics:\n";
  const std::string* category = nullptr;
  for (const Row& r : rows) {
    if (!category || r.category != *category) {
      os << "  " << r.category << "\n";
      category = &r.category;
    }
    os << "    " << r.item << std::string(item_width - r.item.size() + 2, ' ')
       << std::string(value_width - r.value.size(), ' ') << r.value << "\n";
  }
}

}  // namespace plumage
