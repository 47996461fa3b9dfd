// Text in, text out (text.h, docs/robustness.md "Text in, text out"): strings
// read from files are UTF-8 or refused with FILE:LINE:COL, every writer gives
// valid text for what it was given, and a file name with a newline or a byte
// that is not UTF-8 keeps an error message one line of valid text.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/text.h"

using namespace plumage;
using plumage::test::fresh_test_dir;
using plumage::test::plumage_cli;
using plumage::test::plumage_cli_streams;
namespace fs = std::filesystem;

namespace {

constexpr auto npos = std::string_view::npos;

std::string slurp(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p, std::ios::binary).rdbuf();
  return s.str();
}

// A generated feather's .fcurves with its third line (the provenance source)
// replaced by `source_line`.
fs::path feather_with_source(const fs::path& dir, const std::string& source_line) {
  const fs::path base = dir / "base.fcurves";
  if (!fs::exists(base)) {
    EXPECT_EQ(plumage_cli("-q generate --preset osprey-wing-covert -o '" + base.string() + "'").rc, 0);
  }
  std::istringstream in(slurp(base));
  std::string out, line;
  for (int n = 1; std::getline(in, line); ++n) out += (n == 3 ? source_line : line) + "\n";
  const fs::path p = dir / "feather.fcurves";
  std::ofstream(p, std::ios::binary) << out;
  return p;
}

}  // namespace

// RFC 3629's well-formed sequences, and the first offending byte of the forms it
// rules out: a lone continuation byte, overlong forms, surrogates, code points
// above U+10FFFF, a sequence cut short, bytes that never occur.
TEST(Utf8, WellFormedTextPassesAndTheFirstBadByteIsFound) {
  for (const std::string ok : {"", "plain ASCII", "Gr\xC3\xBCnspecht", "\xE2\x82\xAC 20", "\xE9\xB3\xA5",
                               "\xF0\x9F\x90\xA6 bird", "\xEF\xBF\xBD", "\xF4\x8F\xBF\xBF", "\xED\x9F\xBF"})
    EXPECT_EQ(invalid_utf8_at(ok), npos) << ok;
  const std::pair<std::string, std::size_t> bad[] = {
      {"ab\x80", 2},             // a continuation byte alone
      {"\xC0\xAF", 0},           // overlong '/'
      {"x\xC1\xBF", 1},          // overlong
      {"\xE0\x80\xAF", 0},       // overlong, 3 bytes
      {"\xF0\x80\x80\xAF", 0},   // overlong, 4 bytes
      {"ok \xED\xA0\x80", 3},    // a surrogate (U+D800)
      {"\xF4\x90\x80\x80", 0},   // above U+10FFFF
      {"\xF5\x80\x80\x80", 0},   // never a lead byte
      {"tail \xE2\x82", 5},      // cut short at the end
      {"\xE2\x82z", 0},          // cut short in the middle
      {"\xFF", 0},
      {"\xC3\xBC\xFE", 2},
  };
  for (const auto& [s, at] : bad) EXPECT_EQ(invalid_utf8_at(s), at) << printable(s);
}

TEST(Utf8, PrintableIsOneLineOfValidTextAndIdempotent) {
  EXPECT_EQ(printable("a\nb\tc\rd\x01" "e\x7F"), "a\\nb\\tc\\rd\\x01e\\x7F");
  EXPECT_EQ(printable("bad\xFFname"), "bad\\xFFname");
  EXPECT_EQ(printable("Gr\xC3\xBCn \xF0\x9F\x90\xA6"), "Gr\xC3\xBCn \xF0\x9F\x90\xA6");
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255), len(0, 40);
  for (int k = 0; k < 2000; ++k) {
    std::string s(std::size_t(len(rng)), '\0');
    for (char& c : s) c = char(byte(rng));
    const std::string p = printable(s);
    EXPECT_EQ(invalid_utf8_at(p), npos);
    for (const unsigned char c : p) EXPECT_TRUE(c >= 0x20 && c != 0x7F);
    EXPECT_EQ(printable(p), p);
  }
}

TEST(TextInTextOut, ACurveFileThatIsNotUtf8IsRefusedAtItsByte) {
  const fs::path dir = fresh_test_dir("text_refused");
  const fs::path f = feather_with_source(dir, "source \"bad \xFF byte\"");
  for (const std::string& cmd :
       std::vector<std::string>{"info", "info --json", "export -f mitsuba -o '" + (dir / "m.txt").string() + "'"}) {
    const auto r = plumage_cli_streams(cmd + " '" + f.string() + "'");
    EXPECT_EQ(r.rc, 1) << cmd;
    EXPECT_NE(r.err.find(f.string() + ":3:13: byte 0xFF is not UTF-8 text"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "m.txt"));
  fs::remove_all(dir);
}

TEST(TextInTextOut, EveryWriterGivesValidTextForAnyUtf8Source) {
  // Quotes, a backslash, XML's specials, a comment's "--", and letters from
  // beyond ASCII reach JSON, the Mitsuba XML, the Blender script, pbrt and OBJ.
  const std::string source = "Gr\xC3\xBCnspecht <&\\\"quote\\\"> -- \\\\ back \xF0\x9F\x90\xA6";
  const std::string expected = "Gr\xC3\xBCnspecht <&\"quote\"> -- \\ back \xF0\x9F\x90\xA6";
  const fs::path dir = fresh_test_dir("text_writers");
  const fs::path f = feather_with_source(dir, "source \"" + source + "\"");
  const auto info = plumage_cli_streams("info --json '" + f.string() + "'");
  ASSERT_EQ(info.rc, 0) << info.err;
  const nlohmann::json j = nlohmann::json::parse(info.out);
  EXPECT_NE(j.dump().find(nlohmann::json(expected).dump()), std::string::npos) << info.out;
  for (const std::string format : {"pbrt", "pbrt-v3", "mitsuba", "blender", "obj", "fcurves"}) {
    const fs::path out = dir / ("scene." + format + ".txt");
    ASSERT_EQ(plumage_cli("-q export '" + f.string() + "' -f " + format + " -o '" + out.string() + "'").rc, 0) << format;
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.path().filename().string().rfind("scene." + format, 0) != 0) continue;
      const std::string text = slurp(e.path());
      EXPECT_EQ(invalid_utf8_at(text), npos) << e.path();
      if (e.path().extension() == ".xml") {
        // Well-formed where the source lands: in a comment, with no "--" inside it.
        const std::size_t open = text.find("<!--"), close = text.find("-->", open);
        ASSERT_NE(close, std::string::npos);
        EXPECT_EQ(text.substr(open + 4, close - open - 4).find("--"), std::string::npos);
      }
    }
  }
  fs::remove_all(dir);
}

TEST(TextInTextOut, FileNamesWithNewlinesOrBadBytesKeepMessagesOneLine) {
  const fs::path dir = fresh_test_dir("text_names");
  for (const std::string name : {"new\nline.fcurves", "bad\xFFname.fcurves", "tab\there.png"}) {
    const auto r = plumage_cli_streams("info '" + (dir / name).string() + "'");
    EXPECT_EQ(r.rc, 1);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(invalid_utf8_at(r.err), npos) << r.err;
    EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
  }
  fs::remove_all(dir);
}

TEST(TextInTextOut, AnOutputNamingAPhotoWhosePathIsNotUtf8IsValidJson) {
  // A Linux file name may hold any byte; the layout that names it is still JSON.
  const fs::path dir = fresh_test_dir("text_layout");
  const fs::path curves = dir / "f.fcurves", photo = dir / "photo\xFF.png";
  ASSERT_EQ(plumage_cli("-q generate --preset osprey-wing-covert -o '" + curves.string() + "' --preview '" +
                        photo.string() + "'")
                .rc,
            0);
  ASSERT_TRUE(fs::exists(photo));
  const auto r = plumage_cli_streams("-q analyze '" + photo.string() + "' -o '" + (dir / "l.json").string() + "'");
  ASSERT_EQ(r.rc, 0) << r.err;
  const std::string text = slurp(dir / "l.json");
  EXPECT_EQ(invalid_utf8_at(text), npos);
  EXPECT_NO_THROW((void)nlohmann::json::parse(text));
  fs::remove_all(dir);
}

// Bounded work on hostile sizes (issue 37 item 7): a .fcurves is judged by its
// first 4 KiB before it is read whole, so a 900 MB sparse file of zeros is
// refused at its first byte, its peak resident size (from wait4) that of a run
// refusing a one-line file, not 900 MB more. (A spawned child's peak counts its
// parent's until exec, so the test compares two children of the same parent.)
TEST(TextInTextOut, A900MegabyteFileOfZerosIsRefusedBeforeItIsRead) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's shadow memory makes the resident size meaningless";
#endif
  const fs::path dir = fresh_test_dir("text_sparse");
  const fs::path zeros = dir / "zeros.fcurves", small = dir / "small.fcurves", err = dir / "err.txt";
  fs::resize_file((std::ofstream(zeros), zeros), 900ull << 20);  // sparse: no disk taken
  std::ofstream(small) << "not a curve file\n";
  // Peak resident KiB of `plumage info FILE` (ru_maxrss is in KiB on Linux), and what it printed.
  auto info = [&](const fs::path& f, std::string& printed) {
    const pid_t pid = plumage::test::spawn_plumage({"info", f.string()}, err);
    EXPECT_GT(pid, 0);
    int status = 0;
    struct rusage usage {};
    EXPECT_EQ(::wait4(pid, &status, 0, &usage), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1);
    printed = slurp(err);
    return usage.ru_maxrss;
  };
  std::string printed;
  const long baseline = info(small, printed);
  const long peak = info(zeros, printed);
  EXPECT_NE(printed.find(zeros.string() + ":1:1: byte 0x00 is not UTF-8 text"), std::string::npos) << printed;
  EXPECT_LT(peak, baseline + 100L * 1024) << "peak resident KiB, against " << baseline << " for a one-line file";
  fs::remove_all(dir);
}

// JSON inputs (layouts, parameter files, rigs) are judged by their first 4 KiB
// like curve files: a large file of zeros, of binary, or of text that is not a
// JSON object is refused at its first bad byte without being read whole; the
// three readers share one JSON parser and report FILE:LINE:COL the same way.
TEST(TextInTextOut, LargeJsonInputsAreJudgedByTheirStart) {
  const fs::path dir = fresh_test_dir("text_json");
  const fs::path zeros = dir / "zeros.json", binary = dir / "binary.json", words = dir / "words.json";
  fs::resize_file((std::ofstream(zeros), zeros), 900ull << 20);  // sparse: no disk taken
  write_file_atomic(binary, std::string(8000, '\xFF'));
  write_file_atomic(words, "\n  " + std::string(8000, 'a'));
  const struct {
    fs::path file;
    std::string expect;
  } cases[] = {
      {zeros, zeros.string() + ":1:1: byte 0x00 is not UTF-8 text"},
      {binary, binary.string() + ":1:1: byte 0xFF is not UTF-8 text"},
      {words, words.string() + ":2:3: invalid JSON: expected '{' to open the file's object, found 'a'"},
  };
  const std::string out = " -o '" + (dir / "x.fcurves").string() + "'";
  const std::string render = "render '" + (dir / "missing.fcurves").string() + "' -o '" + (dir / "x.png").string() + "'";
  for (const auto& c : cases)
    for (const std::string& args : {"generate --params '" + c.file.string() + "'" + out,
                                    "generate --layout '" + c.file.string() + "'" + out,
                                    render + " --rig '" + c.file.string() + "'"}) {
      const auto r = plumage_cli_streams(args);
      EXPECT_EQ(r.rc, 1) << args;
      EXPECT_NE(r.err.find(c.expect), std::string::npos) << args << "\n" << r.err;
    }
  // A small file is read whole and parsed: the same error form at its line and column.
  write_file_atomic(dir / "bad.json", "{\n  \"leds\": [,]\n}\n");
  for (const std::string& args : {"generate --params '" + (dir / "bad.json").string() + "'" + out,
                                  "generate --layout '" + (dir / "bad.json").string() + "'" + out,
                                  render + " --rig '" + (dir / "bad.json").string() + "'"}) {
    const auto r = plumage_cli_streams(args);
    EXPECT_EQ(r.rc, 1) << args;
    EXPECT_NE(r.err.find("bad.json:2:12: invalid JSON: syntax error"), std::string::npos) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "x.fcurves"));
  EXPECT_FALSE(fs::exists(dir / "x.png"));
  fs::remove_all(dir);
}
