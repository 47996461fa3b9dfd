#pragma once
// Named statistics counters, declared where the work happens and printed by
// `--stats` at the end of a run, grouped by category ("Renderer/Rays traced").
//   static plumage::StatCounter rays("Renderer/Rays traced");
//   rays += n;   // cheap: relaxed atomic add
#include <atomic>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>

namespace plumage {

class StatCounter {
 public:
  explicit StatCounter(const char* name);  // registers itself; `name` must outlive it
  ~StatCounter();                          // unregisters itself
  StatCounter(const StatCounter&) = delete;
  StatCounter& operator=(const StatCounter&) = delete;
  StatCounter& operator+=(std::int64_t n) { v_.fetch_add(n, std::memory_order_relaxed); return *this; }
  StatCounter& operator++() { return *this += 1; }
  std::int64_t value() const { return v_.load(std::memory_order_relaxed); }
  void reset() { v_.store(0, std::memory_order_relaxed); }
  const char* name() const { return name_; }

 private:
  const char* name_;
  std::atomic<std::int64_t> v_{0};
};

// Timings and one-off values recorded during a run (e.g. "Time/BVH build (s)").
void stats_set_value(const std::string& name, double value);
// Adds to a value (from 0 when not yet recorded), e.g. the time of each of several
// renders in one run; returns the new total.
double stats_add_value(const std::string& name, double value);

// All counters and values, name -> value.
std::map<std::string, double> stats_snapshot();
void stats_reset();
// Prints every counter and value, zeros included, grouped by category, with
// the names and the values each in an aligned column.
void stats_print(std::ostream& os);

}  // namespace plumage
