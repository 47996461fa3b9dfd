// Outputs written all or none (FileBatch), inputs that must be regular files
// (check_input_file), the image reader's guards (megapixels, cut-short files)
// and the capture of decoders' stderr lines.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/common/stderr_capture.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

class FileBatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("plumage_file_batch_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  int files() const {
    int n = 0;
    for ([[maybe_unused]] auto& e : fs::directory_iterator(dir_)) ++n;
    return n;
  }
  fs::path dir_;
};

TEST_F(FileBatchTest, CommitWritesEveryOutput) {
  write_file_atomic(dir_ / "a.txt", "old a");
  FileBatch batch;
  batch.stage_text(dir_ / "a.txt", "new a");
  batch.stage_text(dir_ / "b.txt", "new b");
  EXPECT_EQ(read_file(dir_ / "a.txt"), "old a");  // nothing is in place before commit()
  EXPECT_FALSE(fs::exists(dir_ / "b.txt"));
  batch.commit();
  EXPECT_EQ(read_file(dir_ / "a.txt"), "new a");
  EXPECT_EQ(read_file(dir_ / "b.txt"), "new b");
  EXPECT_EQ(files(), 2);  // no temporary or backup file left
}

TEST_F(FileBatchTest, AFailedOutputLeavesEveryTargetAsItWas) {
  write_file_atomic(dir_ / "a.txt", "old a");
  try {
    FileBatch batch;
    batch.stage_text(dir_ / "a.txt", "new a");
    batch.stage(dir_ / "b.png", [](const fs::path&) { throw Error("the preview failed"); });
    batch.commit();
    ADD_FAILURE() << "the second output's failure should propagate";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "the preview failed");
  }
  EXPECT_EQ(read_file(dir_ / "a.txt"), "old a");
  EXPECT_EQ(files(), 1);
  try {
    FileBatch batch;
    batch.stage_text(dir_ / "a.txt", "new a");
    batch.stage_text(dir_ / "missing" / "b.txt", "b");
    ADD_FAILURE() << "a missing folder should be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_file(dir_ / "a.txt"), "old a");
  EXPECT_EQ(files(), 1);
}

// A rename that fails part-way through commit() puts back what it had replaced.
TEST_F(FileBatchTest, AFailedRenameRollsBackTheEarlierOnes) {
  write_file_atomic(dir_ / "a.txt", "old a");
  FileBatch batch;
  batch.stage_text(dir_ / "new.txt", "new");
  batch.stage_text(dir_ / "a.txt", "new a");
  // A non-empty folder appears where b.txt should go after it was staged (one
  // there before is refused when staging).
  batch.stage(dir_ / "b.txt", [&](const fs::path& tmp) {
    std::ofstream(tmp) << "new b";
    fs::create_directories(dir_ / "b.txt" / "inside");
  });
  EXPECT_THROW(batch.commit(), Error);
  EXPECT_EQ(read_file(dir_ / "a.txt"), "old a");
  EXPECT_FALSE(fs::exists(dir_ / "new.txt"));
  EXPECT_TRUE(fs::is_directory(dir_ / "b.txt" / "inside"));
  EXPECT_EQ(files(), 2);  // a.txt and the folder: no temporary or backup file
}

TEST_F(FileBatchTest, TheSameOutputTwiceIsRefused) {
  FileBatch batch;
  batch.stage_text(dir_ / "a.txt", "1");
  EXPECT_THROW(batch.stage_text(dir_ / "." / "a.txt", "2"), Error);
}

TEST_F(FileBatchTest, InputsMustBeRegularFiles) {
  write_file_atomic(dir_ / "a.txt", "12345");
  EXPECT_EQ(check_input_file(dir_ / "a.txt", "a file"), 5u);
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  for (const fs::path& p : {dir_ / "fifo", fs::path("/dev/zero"), fs::path("/dev/null"), dir_, dir_ / "missing"}) {
    EXPECT_THROW(check_input_file(p, "a file"), Error) << p;
    EXPECT_THROW(read_file(p), Error) << p;  // and nothing hangs
    EXPECT_THROW(read_image(p), Error) << p;
  }
  try {
    read_image(dir_ / "fifo");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is not a regular file"), std::string::npos) << e.what();
  }
}

TEST_F(FileBatchTest, ImageReaderRefusesHugeAndCutShortFiles) {
  write_image(dir_ / "ok.png", Image(64, 48, 3, 0.5f));
  write_image(dir_ / "ok.jpg", Image(64, 48, 3, 0.5f));
  EXPECT_EQ(damage_of(dir_ / "ok.png"), "");
  EXPECT_EQ(damage_of(dir_ / "ok.jpg"), "");
  EXPECT_EQ(read_image(dir_ / "ok.png").width, 64);
  // Above a limit of 0.001 megapixels: refused from the header, with the size and the limit.
  try {
    read_image(dir_ / "ok.png", true, 0.001);
    ADD_FAILURE() << "a 64x48 image is above 0.001 megapixels";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("64x48x3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0.001-megapixel limit"), std::string::npos) << e.what();
  }
  // A side above kMaxImageSide (decoders take scratch per block of up to 256 scanlines)
  // or more than kMaxImageChannels channels: refused from the header, inside the
  // megapixel limit. One pixel more or fewer decides.
  write_image(dir_ / "wide.exr", Image(kMaxImageSide + 1, 1, 1, 0.5f));
  write_image(dir_ / "widest_ok.exr", Image(kMaxImageSide, 1, 1, 0.5f));
  write_image(dir_ / "channels.exr", Image(2, 2, kMaxImageChannels + 1, 0.5f));
  write_image(dir_ / "channels_ok.exr", Image(2, 2, kMaxImageChannels, 0.5f));
  try {
    read_image(dir_ / "wide.exr");
    ADD_FAILURE() << "a side of " << kMaxImageSide + 1 << " pixels was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxImageSide) + "-pixel limit of a side"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read_image(dir_ / "widest_ok.exr").width, kMaxImageSide);
  try {
    read_image(dir_ / "channels.exr");
    ADD_FAILURE() << kMaxImageChannels + 1 << " channels were read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxImageChannels + 1) + " channels"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read_image(dir_ / "channels_ok.exr").channels, kMaxImageChannels);
  for (const char* name : {"ok.png", "ok.jpg"}) {
    const std::string bytes = read_file(dir_ / name);
    const fs::path cut = dir_ / (std::string("cut_") + name);
    write_file_atomic(cut, bytes.substr(0, bytes.size() - 20));
    EXPECT_NE(damage_of(cut).find("cut short"), std::string::npos) << name;
    StderrCapture nothing_else;  // and the decoders print nothing
    EXPECT_THROW(read_image(cut), Error) << name;
    EXPECT_EQ(nothing_else.text(), "") << name;
  }
}

// An OpenEXR header whose attribute claims more bytes than the file holds would
// make OpenEXR allocate that much while opening it (found by fuzz_image).
TEST_F(FileBatchTest, ImageReaderRefusesADamagedExrHeader) {
  write_image(dir_ / "ok.exr", Image(16, 8, 3, 0.25f));
  EXPECT_EQ(damage_of(dir_ / "ok.exr"), "");
  EXPECT_EQ(read_image(dir_ / "ok.exr").height, 8);
  std::string bytes = read_file(dir_ / "ok.exr");
  const std::size_t name_end = bytes.find('\0', 8), type_end = bytes.find('\0', name_end + 1);
  ASSERT_LT(type_end + 5, bytes.size());
  bytes.replace(type_end + 1, 4, std::string("\x00\x00\x00\x5e", 4));  // 1.5 GB
  write_file_atomic(dir_ / "bad.exr", bytes);
  EXPECT_NE(damage_of(dir_ / "bad.exr").find("past the end of the file"), std::string::npos) << damage_of(dir_ / "bad.exr");
  EXPECT_THROW(read_image(dir_ / "bad.exr"), Error);
}

// OpenEXR takes its line buffers while opening a file: a data window 2^24 pixels
// wide (inside damage_of's sanity bound) with 16 channels under DWAB compression
// (blocks of 256 lines) would ask for 2^24 x 16 x 4 x 256 bytes = 64 GiB before
// any size check that looks at an opened file. read_image reads the header alone
// first and refuses it by the side limit.
TEST_F(FileBatchTest, ImageReaderRefusesAnExrAboveTheLimitsBeforeOpeningIt) {
  write_image(dir_ / "ok.exr", Image(16, 1, kMaxImageChannels, 0.25f));
  std::string bytes = read_file(dir_ / "ok.exr");
  const auto value_of = [&](const std::string& name_and_type) {
    const std::size_t at = bytes.find(name_and_type);
    EXPECT_NE(at, std::string::npos) << name_and_type;
    return at + name_and_type.size() + 4;  // past the int32 size
  };
  const std::size_t window = value_of(std::string("dataWindow\0box2i\0", 17));
  const std::int32_t x_max = (1 << 24) - 1;
  std::memcpy(&bytes[window + 8], &x_max, 4);  // little-endian, as OpenEXR stores it
  bytes[value_of(std::string("compression\0compression\0", 24))] = 9;  // DWAB
  write_file_atomic(dir_ / "huge_block.exr", bytes);
  EXPECT_EQ(damage_of(dir_ / "huge_block.exr"), "");
  try {
    read_image(dir_ / "huge_block.exr");
    ADD_FAILURE() << "a 2^24-pixel-wide EXR was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxImageSide) + "-pixel limit of a side"), std::string::npos)
        << e.what();
  }
}

TEST(StderrCaptureTest, HoldsBackWhatIsPrintedAndRestoresStderr) {
  std::string text;
  {
    StderrCapture capture;
    std::fprintf(stderr, "libfoo warning: one\nlibfoo error: two\n");
    text = capture.text();
  }
  EXPECT_EQ(text, "libfoo warning: one; libfoo error: two");
  StderrCapture again;  // stderr works again and can be captured again
  std::fprintf(stderr, "three\n");
  EXPECT_EQ(again.text(), "three");
}

// PLUMAGE_KEEP_STDERR=1 (set by scripts/fuzz.sh) leaves stderr alone, so that a
// sanitizer report from inside a decoder is not captured and lost.
TEST(StderrCaptureTest, KeepStderrEnvironmentTurnsCapturingOff) {
  const char* before = std::getenv("PLUMAGE_KEEP_STDERR");
  const std::string saved = before != nullptr ? before : "";
  ::setenv("PLUMAGE_KEEP_STDERR", "1", 1);
  std::string kept;
  {
    StderrCapture capture;
    std::fprintf(stderr, "(this line belongs on the test's stderr)\n");
    kept = capture.text();
  }
  ::setenv("PLUMAGE_KEEP_STDERR", "0", 1);
  std::string captured;
  {
    StderrCapture capture;
    std::fprintf(stderr, "captured\n");
    captured = capture.text();
  }
  if (before != nullptr)
    ::setenv("PLUMAGE_KEEP_STDERR", saved.c_str(), 1);
  else
    ::unsetenv("PLUMAGE_KEEP_STDERR");
  EXPECT_EQ(kept, "");
  EXPECT_EQ(captured, "captured");
}

}  // namespace
