#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

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

// The message of a failed rename must carry the reason of the rename itself,
// not of the clean-up after it (it once read "cannot rename ...: Success").
TEST(AtomicFile, FailedRenameReportsTheRealReason) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("plumage_atomic_rename_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path target = dir / "taken";
  fs::create_directories(dir);
  try {
    // A non-empty directory appears where the file should go while it is written
    // (one there before is refused up front, below).
    write_via_temp(target, [&](const fs::path& tmp) {
      std::ofstream(tmp) << "data";
      fs::create_directories(target / "inside");
    });
    ADD_FAILURE() << "renaming a file onto a directory should fail";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("cannot rename"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("Success"), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::make_error_code(std::errc::is_a_directory).message()), std::string::npos) << msg;
  }
  try {
    write_file_atomic(target, "data");
    ADD_FAILURE() << "a directory named as the output should be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory: give a file name"), std::string::npos) << e.what();
  }
  // The temporary file is gone and the directory is untouched.
  int n = 0;
  for ([[maybe_unused]] auto& e : fs::directory_iterator(dir)) ++n;
  EXPECT_EQ(n, 1);
  EXPECT_TRUE(fs::is_directory(target / "inside"));
  fs::remove_all(dir);
}

// A 250-character name is legal, and its temporary (".NAME.tmp-PID-N", its stem
// cut to fit) is too: the file is written. A name longer than a file name may be
// fails with the system's reason, and leaves nothing behind.
TEST(AtomicFile, LongNamesAreWrittenOrRefusedWithTheRealReason) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("plumage_atomic_open_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path fits = dir / (std::string(246, 'n') + ".png");
  write_file_atomic(fits, "data");
  EXPECT_EQ(read_file(fits), "data");
  int n = 0;
  for ([[maybe_unused]] auto& e : fs::directory_iterator(dir)) ++n;
  EXPECT_EQ(n, 1) << "only the file itself";
  fs::remove(fits);
  try {
    write_file_atomic(dir / std::string(300, 'n'), "data");
    ADD_FAILURE() << "a name over 255 characters should not be written";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(std::make_error_code(std::errc::filename_too_long).message()), std::string::npos) << msg;
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}
