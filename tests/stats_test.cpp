// Statistics counters (stats.h): registration, snapshot, reset and printing.
#include <gtest/gtest.h>

#include <sstream>
#include <thread>
#include <vector>

#include "plumage/common/stats.h"

using namespace plumage;

namespace {
StatCounter g_hits("StatsTest/Hits");
StatCounter g_misses("StatsTest/Misses");
}  // namespace

TEST(Stats, CountersAppearInTheSnapshot) {
  stats_reset();
  g_hits += 5;
  ++g_hits;
  auto snap = stats_snapshot();
  ASSERT_TRUE(snap.count("StatsTest/Hits"));
  ASSERT_TRUE(snap.count("StatsTest/Misses"));
  EXPECT_EQ(snap["StatsTest/Hits"], 6);
  EXPECT_EQ(snap["StatsTest/Misses"], 0);
  EXPECT_EQ(g_hits.value(), 6);
}

TEST(Stats, ResetZeroesCountersAndClearsValues) {
  g_hits += 3;
  stats_set_value("StatsTest/Time (s)", 1.5);
  EXPECT_EQ(stats_snapshot()["StatsTest/Time (s)"], 1.5);
  stats_reset();
  const auto snap = stats_snapshot();
  EXPECT_EQ(snap.at("StatsTest/Hits"), 0);
  EXPECT_EQ(snap.count("StatsTest/Time (s)"), 0u);
  EXPECT_EQ(g_hits.value(), 0);
}

TEST(Stats, AddedValuesAccumulateFromZeroUntilReset) {
  stats_reset();
  EXPECT_EQ(stats_add_value("StatsTest/Render (s)", 1.25), 1.25);
  EXPECT_EQ(stats_add_value("StatsTest/Render (s)", 2.5), 3.75);
  EXPECT_EQ(stats_snapshot().at("StatsTest/Render (s)"), 3.75);
  stats_reset();
  EXPECT_EQ(stats_add_value("StatsTest/Render (s)", 0.5), 0.5);
}

TEST(Stats, CountersWithTheSameNameAreSummed) {
  stats_reset();
  StatCounter a("StatsTest/Shared"), b("StatsTest/Shared");
  a += 2;
  b += 40;
  EXPECT_EQ(stats_snapshot().at("StatsTest/Shared"), 42);
}

TEST(Stats, AShortLivedCounterUnregisters) {
  {
    StatCounter temp("StatsTest/Temporary");
    temp += 7;
    EXPECT_EQ(stats_snapshot().at("StatsTest/Temporary"), 7);
  }
  // Reading it now would be a use after free (caught by the sanitizer build).
  EXPECT_EQ(stats_snapshot().count("StatsTest/Temporary"), 0u);
}

TEST(Stats, ConcurrentIncrementsAreNotLost) {
  stats_reset();
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i)
    threads.emplace_back([] {
      for (int k = 0; k < 100000; ++k) ++g_misses;
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(g_misses.value(), 400000);
}

TEST(Stats, PrintGroupsByCategoryAndShowsZeros) {
  stats_reset();
  g_hits += 1234567;
  stats_set_value("StatsTest/Ratio", 0.25);
  std::ostringstream os;
  stats_print(os);
  const std::string out = os.str();
  EXPECT_EQ(out.rfind("Statistics:", 0), 0u) << out;
  const auto category = out.find("\n  StatsTest\n");
  ASSERT_NE(category, std::string::npos) << out;
  const auto hits = out.find("    Hits ");
  ASSERT_NE(hits, std::string::npos) << out;
  EXPECT_GT(hits, category);
  EXPECT_NE(out.find("1234567"), std::string::npos) << out;
  EXPECT_NE(out.find("0.25"), std::string::npos) << out;
  // A counter that reads zero is shown, with its zero: "no NaN samples" is news.
  const auto misses = out.find("    Misses ");
  ASSERT_NE(misses, std::string::npos) << out;
  EXPECT_EQ(out.substr(out.find('\n', misses) - 2, 2), " 0") << out;
  // One heading per category, however many items it has.
  EXPECT_EQ(out.find("\n  StatsTest\n", category + 1), std::string::npos) << out;
  stats_reset();
}

TEST(Stats, PrintAlignsNamesAndValuesInColumns) {
  stats_reset();
  StatCounter long_name("StatsTest/A counter whose name is much longer than forty characters");
  long_name += 3;
  g_hits += 1234567;
  std::istringstream in([] {
    std::ostringstream os;
    stats_print(os);
    return os.str();
  }());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "Statistics:");
  std::size_t width = 0, items = 0;
  while (std::getline(in, line)) {
    if (line.rfind("    ", 0) != 0) {  // a category heading
      EXPECT_EQ(line.rfind("  ", 0), 0u) << line;
      continue;
    }
    ++items;
    EXPECT_NE(line[4], ' ') << "names start in one column: " << line;
    EXPECT_NE(line.back(), ' ') << line;
    if (width == 0) width = line.size();
    EXPECT_EQ(line.size(), width) << "values end in one column: " << line;
    // At least two spaces between the name and its value.
    const auto gap = line.find_last_of(' ');
    EXPECT_EQ(line.substr(gap - 1, 2), "  ") << line;
  }
  EXPECT_GE(items, 3u);
  stats_reset();
}
