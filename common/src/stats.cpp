#include "plumage/common/stats.h"

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

void stats_print(std::ostream& os) {
  std::string category;
  os << "Statistics:\n";
  for (const auto& [name, value] : stats_snapshot()) {
    if (value == 0) continue;
    const auto slash = name.find('/');
    const std::string cat = slash == std::string::npos ? "" : name.substr(0, slash);
    const std::string item = slash == std::string::npos ? name : name.substr(slash + 1);
    if (cat != category) {
      os << "  " << cat << "\n";
      category = cat;
    }
    char buf[64];
    if (value == double(static_cast<long long>(value)) && std::abs(value) < 1e15)
      std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(value));
    else
      std::snprintf(buf, sizeof buf, "%.6g", value);
    os << "    " << item << std::string(item.size() < 40 ? 40 - item.size() : 1, ' ') << buf << "\n";
  }
}

}  // namespace plumage
