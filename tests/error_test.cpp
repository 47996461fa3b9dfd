#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"

using namespace plumage;

TEST(Error, FormatsPlace) {
  EXPECT_STREQ(Error(Location{"a.fcurves", 3, 7}, "expected a number").what(),
               "a.fcurves:3:7: expected a number");
  EXPECT_STREQ(Error(Location{"a.fcurves", 3, 0}, "x").what(), "a.fcurves:3: x");
  EXPECT_STREQ(Error("plain").what(), "plain");
}

TEST(AtomicFile, FailedWriteLeavesOldFileIntact) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("plumage_atomic_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path f = dir / "out.txt";
  write_file_atomic(f, "first");
  EXPECT_THROW(write_via_temp(f, [](const fs::path& tmp) {
                 write_file_atomic(tmp, "partial");
                 throw Error("simulated failure");
               }),
               Error);
  EXPECT_EQ(read_file(f), "first");
  // No temporary files left behind.
  int n = 0;
  for ([[maybe_unused]] auto& e : fs::directory_iterator(dir)) ++n;
  EXPECT_EQ(n, 1);
  EXPECT_THROW(write_file_atomic(dir / "missing" / "x.txt", "y"), Error);
  fs::remove_all(dir);
}
