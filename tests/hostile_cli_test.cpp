// docs/cli.md's promise under hostile input (docs/robustness.md, "Hostile input"),
// table-driven: several hundred command lines as a careless or hostile user might
// type them, over every subcommand and every kind of input (mutated curve files,
// parameters and layouts, damaged, huge and special-file images, absurd numbers,
// unknown names, unwritable outputs). Every failing case must
//   * exit with its documented status (2 usage, 1 failure),
//   * print exactly one line on stderr, starting `plumage: error: `,
//   * leave its output folder byte-identical: the outputs that were there before
//     (sentinel files) unchanged, nothing new, no temporary file left;
// and every case that succeeds must write images with no NaN or Inf pixel.
// Each case runs the built binary in a folder of its own, several at a time.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.h"
#include "feather_samples.h"
#include "synthetic_feather.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/image.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

struct Case {
  std::string args;  // after `plumage -q`; {d} is the shared input folder, {o} the case's own folder
  int rc;            // the documented exit status
  std::string mention = {};  // the error line must contain this ({d} replaced), when given
};

// Outputs every case folder holds before its run: a failed run must leave them as they are.
const char* const kSentinels[] = {"out.png",  "out.exr",          "out.fcurves",      "out.json",
                                  "out.csv",  "preview.png",      "overlay.png",      "out.albedo.png",
                                  "out.pbrt", "out_hair.png",     "out_substructure.png"};

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// Every file under `dir` (recursively) and its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    if (e.is_regular_file()) {
      std::ifstream in(e.path(), std::ios::binary);
      std::ostringstream ss;
      ss << in.rdbuf();
      files[rel] = ss.str();
    } else {
      files[rel + "/"] = "";
    }
  }
  return files;
}

bool finite_pixels(const Image& img) {
  return std::all_of(img.pixels.begin(), img.pixels.end(), [](float v) { return std::isfinite(v); });
}

// A PNG whose header claims `w` x `h` pixels (valid signature, IHDR with its CRC,
// an empty IDAT and IEND): readers must refuse it from the header alone.
std::string png_claiming(std::uint32_t w, std::uint32_t h) {
  auto crc = [](const std::string& bytes) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : bytes) {
      c ^= b;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
  };
  auto be32 = [](std::uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(std::uint32_t(data.size())) + type + data + be32(crc(type + data));
  };
  const std::string ihdr = be32(w) + be32(h) + std::string{8, 2, 0, 0, 0};  // 8-bit RGB
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) +
         chunk("IEND", "");
}

class HostileCli : public ::testing::Test {
 protected:
  static fs::path root_, in_;
  static bool have_layout_;

  // The inputs every case reads, built once: good ones and broken ones. An
  // exception here must fail every case (ctest would count a bare suite-setup
  // failure as skipped tests), so it is kept and reported by SetUp.
  static void SetUpTestSuite() {
    try {
      make_inputs();
    } catch (const std::exception& e) {
      setup_error_ = e.what();
    }
  }
  void SetUp() override {
    if (!setup_error_.empty()) FAIL() << "building the hostile inputs failed: " << setup_error_;
  }
  static inline std::string setup_error_;

  static void make_inputs() {
    root_ = fs::temp_directory_path() / ("plumage_hostile_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    in_ = root_ / "in";
    fs::create_directories(in_ / "dir");
    auto put = [](const std::string& name, const std::string& bytes) { write_file_atomic(in_ / name, bytes); };

    Feather f = samples::sample_feather(4, 5);
    write_fcurves(in_ / "f.fcurves", f);
    const std::string good = format_fcurves(f);
    put("empty.fcurves", "");
    put("garbage.fcurves", "this is not a curve file\n\x01\x02\xff\n");
    put("half.fcurves", good.substr(0, good.size() / 2));
    put("binary.fcurves", std::string("\0\0\0\x7f\xff\xfe", 6) + good);
    put("nul.fcurves", replace_all(good, "\n", std::string("\n\0", 2)));
    // One coordinate far out, one not a number: the reader or the framing must name them.
    {
      Feather far = f;
      far.curves[1].points[0].p.x = 3.4e38f;
      write_fcurves(in_ / "far.fcurves", far);
    }
    {
      // The most barbules the curve format takes, on 100 barbs: 20 million curves,
      // beyond explicit mode's memory ceiling.
      Feather many = samples::sample_feather(100, 5);
      many.left.barbules_per_side = many.right.barbules_per_side = 100000;
      many.left.barbule_radius = many.right.barbule_radius = 0.001f;
      many.left.ramus_radius = many.right.ramus_radius = 0.01f;
      many.left.ribbon_width = many.right.ribbon_width = 0.1f;
      write_fcurves(in_ / "many_barbules.fcurves", many);
    }
    for (const auto& [name, texture] : {std::pair{"tex_huge.fcurves", "huge.png"}, {"tex_dev.fcurves", "/dev/zero"},
                                        {"tex_fifo.fcurves", "fifo"}, {"tex_missing.fcurves", "missing.png"},
                                        {"tex_text.fcurves", "text.png"}, {"tex_trunc.fcurves", "trunc.png"}}) {
      Feather t = f;
      t.albedo.texture = texture;
      t.albedo.rect_min = {-20, 0};
      t.albedo.rect_max = {20, 70};
      write_fcurves(in_ / name, t);
    }

    // Scenes of many feathers (.fscene): damaged scenes, and good scenes whose
    // feather file is missing, damaged, a device or a FIFO.
    {
      const std::string scene = "fscene 1\nfeather a fcurves \"f.fcurves\"\nplace a\nplace a mirror x\nend\n";
      put("empty.fscene", "");
      put("garbage.fscene", "this is not a scene\n\x01\x02\xff\n");
      put("half.fscene", scene.substr(0, scene.size() / 2));
      put("binary.fscene", std::string("\0\0\0\x7f\xff\xfe", 6) + scene);
      put("nul.fscene", replace_all(scene, "\n", std::string("\n\0", 2)));
      put("shear.fscene", "fscene 1\nfeather a fcurves \"f.fcurves\"\nplace a matrix 1 0.5 0 0 0 1 0 0 0 0 1 0\nend\n");
      for (const auto& [name, target] : {std::pair{"to_missing.fscene", "missing.fcurves"}, {"to_garbage.fscene", "garbage.fcurves"},
                                         {"to_fifo.fscene", "fifo.fcurves"}, {"to_dev.fscene", "/dev/zero"},
                                         {"to_dir.fscene", "dir"}, {"to_far.fscene", "far.fcurves"}})
        put(name, "fscene 1\nfeather a fcurves \"" + std::string(target) + "\"\nplace a\nend\n");
    }

    // Images: a feather photo, and damaged, huge, empty and mislabelled ones.
    synthetic::SyntheticFeather sf;
    write_image(in_ / "photo.png", sf.draw());
    write_image(in_ / "photo.jpg", sf.draw());
    write_image(in_ / "small.png", Image(8, 8, 3, 0.5f));
    const std::string png = read_file(in_ / "photo.png"), jpg = read_file(in_ / "photo.jpg");
    put("trunc.png", png.substr(0, png.size() / 2));
    put("trunc.jpg", jpg.substr(0, jpg.size() / 2));
    put("text.png", "just some text, not a picture\n");
    put("empty.png", "");
    put("jpg_named.png", jpg);
    put("huge.png", png_claiming(20000, 20000));
    put("wide.png", png_claiming(1u << 30, 1));
    put("zero.png", png_claiming(0, 0));
    ::mkfifo((in_ / "fifo").c_str(), 0600);
    ::mkfifo((in_ / "fifo.png").c_str(), 0600);
    ::mkfifo((in_ / "fifo.fcurves").c_str(), 0600);

    // Parameters and layouts, good and broken.
    put("bad.json", "{\"shaft\": {\"length\": -3}}\n");
    put("notjson.json", "{ this is not json");
    put("empty.json", "");
    put("array.json", "[1, 2, 3]\n");
    put("deep.json", std::string(100000, '[') + std::string(100000, ']'));
    put("inf.json", "{\"shaft\": {\"length\": 1e999}}\n");
    const auto r = test::plumage_cli_streams("-q analyze '" + (in_ / "photo.png").string() + "' -o '" +
                                             (in_ / "layout.json").string() + "' --mm-per-px 0.1");
    have_layout_ = r.rc == 0;
    if (have_layout_) {
      const std::string layout = read_file(in_ / "layout.json");
      put("layout_trunc.json", layout.substr(0, layout.size() / 2));
      put("layout_noalbedo.json", replace_all(layout, ".albedo.png", ".missing.png"));
      put("layout_huge_albedo.json", replace_all(layout, "layout.feather1.albedo.png", "huge.png"));
      put("layout_dev_albedo.json", replace_all(layout, "layout.feather1.albedo.png", "fifo"));
    }
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }

  // Runs `cases` (several at a time) and checks each against the promise.
  void run_cases(const std::string& suite, const std::vector<Case>& cases) {
    ASSERT_GE(cases.size(), 1u);
    std::atomic<std::size_t> next{0};
    std::mutex report;
    std::vector<std::string> failures;
    auto worker = [&] {
      for (std::size_t i = next++; i < cases.size(); i = next++) {
        const std::string problem = check_case(suite + "_" + std::to_string(i), cases[i]);
        if (!problem.empty()) {
          std::lock_guard<std::mutex> lock(report);
          failures.push_back(problem);
        }
      }
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < 4; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    for (const auto& f : failures) ADD_FAILURE() << f;
    RecordProperty("cases", int(cases.size()));
  }

  static std::string check_case(const std::string& name, const Case& c) {
    const fs::path out = root_ / name;
    fs::create_directories(out);
    for (const char* s : kSentinels) write_file_atomic(out / s, std::string("sentinel ") + s + "\n");
    const auto before = snapshot(out);
    const std::string args = replace_all(replace_all(c.args, "{d}", in_.string()), "{o}", out.string());
    const test::CliStreams r = test::plumage_cli_streams("-q " + args);
    std::ostringstream problem;
    const std::string where = "`plumage -q " + args + "`: ";
    if (r.rc != c.rc) problem << where << "exit " << r.rc << ", expected " << c.rc << "; stderr: " << r.err << "\n";
    const auto after = snapshot(out);
    const std::string mention = replace_all(c.mention, "{d}", in_.string());
    if (!mention.empty() && r.err.find(mention) == std::string::npos)
      problem << where << "the error does not name the culprit '" << mention << "': " << r.err << "\n";
    if (c.rc != 0 && r.err.size() > 400) problem << where << "the error line is " << r.err.size() << " characters\n";
    if (c.rc != 0) {
      const bool one_line = !r.err.empty() && r.err.back() == '\n' && r.err.find('\n') == r.err.size() - 1;
      if (!one_line || r.err.rfind("plumage: error: ", 0) != 0)
        problem << where << "stderr is not one `plumage: error:` line: [" << r.err << "]\n";
      if (after != before) {
        problem << where << "the output folder changed:";
        for (const auto& [file, bytes] : after)
          if (!before.count(file)) problem << " new " << file;
          else if (before.at(file) != bytes) problem << " changed " << file;
        for (const auto& [file, bytes] : before)
          if (!after.count(file)) problem << " removed " << file;
        problem << "\n";
      }
    } else {
      for (const auto& [file, bytes] : after) {
        if (file.find(".tmp-") != std::string::npos || file.find(".old-") != std::string::npos)
          problem << where << "left a temporary file " << file << "\n";
        const std::string ext = fs::path(file).extension().string();
        if ((ext == ".png" || ext == ".exr") && (!before.count(file) || before.at(file) != bytes)) {
          try {
            if (!finite_pixels(read_image(out / file, false))) problem << where << file << " has NaN or Inf pixels\n";
          } catch (const std::exception& e) {
            problem << where << file << " cannot be read back: " << e.what() << "\n";
          }
        }
      }
    }
    std::error_code ec;
    fs::remove_all(out, ec);
    return problem.str();
  }

  // The options of `plumage SUB` whose type (in --help) starts with `type`.
  static std::vector<std::string> options_of_type(const std::string& sub, const std::string& type) {
    const test::CliStreams help = test::plumage_cli_streams(sub + " --help");
    std::vector<std::string> names;
    std::istringstream lines(help.out);
    for (std::string line; std::getline(lines, line);) {
      std::istringstream words(line);
      std::string flags, kind;
      if (!(words >> flags >> kind) || flags.rfind("-", 0) != 0) continue;
      std::string longest;
      std::istringstream parts(flags);
      for (std::string p; std::getline(parts, p, ',');)
        if (p.rfind("--", 0) == 0) longest = p;
      if (!longest.empty() && kind.rfind(type, 0) == 0) names.push_back(longest);
    }
    return names;
  }
};

fs::path HostileCli::root_, HostileCli::in_;
bool HostileCli::have_layout_ = false;

const std::string kRender = "render {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/out.png";
const std::string kCompare = "compare {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/out.png";

// Every floating-point option of every command refuses non-numbers, NaN, Inf and
// floats beyond FLT_MAX, and every unsigned one refuses negatives, with exit 2:
// the options are read from --help, so a new option is covered when it is added.
TEST_F(HostileCli, EveryNumericOptionRefusesNonFiniteAndNegativeUnsigned) {
  const std::pair<std::string, std::string> commands[] = {
      {"render", kRender},
      {"compare", kCompare},
      {"analyze", "analyze {d}/photo.png -o {o}/out.json"},
      {"generate", "generate --preset rock-dove-wing -o {o}/out.fcurves"},
      {"photo-to-feather", "photo-to-feather {d}/photo.png -o {o}/ptf"},
      {"bench", "bench --csv {o}/out.csv --plot {o}/out.png"},
      {"export", "export {d}/f.fcurves -o {o}/out.pbrt"},
      {"info", "info {d}/f.fcurves"},
  };
  std::vector<Case> cases;
  std::size_t floats = 0;
  for (const auto& [sub, base] : commands) {
    for (const std::string& opt : options_of_type(sub, "FLOAT")) {
      ++floats;
      for (const char* v : {"nan", "-inf", "1e39", "abc"})
        cases.push_back({base + " " + opt + " " + v, 2});
    }
    for (const std::string& opt : options_of_type(sub, "UINT"))
      for (const char* v : {"-1", "-18446744073709551615", "x"}) cases.push_back({base + " " + opt + " " + v, 2});
  }
  // render has 20 and more float options: the --help parsing must have found them.
  EXPECT_GE(floats, 30u);
  run_cases("numeric", cases);
}

TEST_F(HostileCli, CommandLineUsage) {
  std::vector<Case> cases = {
      {"", 2},
      {"frobnicate", 2},
      {"--bogus render", 2},
      {"render", 2},
      {"render {d}/f.fcurves", 2},
      {"render -o {o}/out.png", 2},
      {kRender + " --bogus", 2},
      {kRender + " extra-positional", 2},
      {kRender + " --spp", 2},
      {"compare", 2},
      {"analyze", 2},
      {"analyze {d}/photo.png", 2},
      {"generate --preset rock-dove-wing --params {d}/bad.json -o {o}/out.fcurves", 2},
      {"generate --preset rock-dove-wing --layout {d}/layout.json -o {o}/out.fcurves", 2},
      {"export", 2},
      {"export {d}/f.fcurves", 2},
      {"export {d}/f.fcurves -o {o}/out.usd", 2},
      {"export {d}/f.fcurves --format usd -o {o}/out.pbrt", 2},
      {"info", 2},
      {"info {d}/f.fcurves --bogus", 2},
      {"photo-to-feather", 2},
      {"photo-to-feather {d}/photo.png", 2},
      {"bench --bogus", 2},
  };
  // Named values: unknown names, wrong case, empty, and a close miss.
  const std::pair<std::string, std::vector<std::string>> enums[] = {
      {"--shading", {"bogus", "Hair", "", "hair,substructure", "explicit2"}},
      {"--aov", {"depth", "Structure", ""}},
      {"--backdrop", {"grey", "WHITE", ""}},
      {"--projection", {"fisheye", "ortho", ""}},
      {"--light-pick", {"nearest", "Uniform", ""}},
      {"--sampler", {"halton", "Sobol", ""}},
  };
  for (const auto& [opt, values] : enums)
    for (const auto& v : values) {
      cases.push_back({kRender + " " + opt + " '" + v + "'", 2});
      if (opt != "--shading" && opt != "--aov" && opt != "--sampler")
        cases.push_back({kCompare + " " + opt + " '" + v + "'", 2});
    }
  for (const char* v : {"fisheye", ""}) cases.push_back({"bench --csv {o}/out.csv --reference-mode '" + std::string(v) + "'", 2});
  for (const char* v : {"nearest", ""}) cases.push_back({"bench --csv {o}/out.csv --light-pick '" + std::string(v) + "'", 2});
  // Sizes and counts.
  for (const char* r : {"65536x65536", "16385x1", "9000x9000", "0x8", "8x0", "-8x8", "8x-8", "12by8", "8x", "x8", "8",
                        "8x8x8", "99999999999x1", "1x99999999999", "8 x 8", "0x0", "nanxnan", "1e3x8", "''"}) {
    cases.push_back({kRender + " --resolution '" + std::string(r) + "'", 2});
    cases.push_back({kCompare + " --resolution '" + std::string(r) + "'", 2});
  }
  cases.push_back({"bench --csv {o}/out.csv --resolution 65536x65536", 2});
  for (const char* v : {"0", "-1", "2000000", "x", "1.5"}) {
    cases.push_back({kRender + " --spp " + v, 2});
    cases.push_back({kRender + " --adaptive --min-spp " + v, 2});
  }
  for (const char* v : {"-1", "100000", "x"}) {
    cases.push_back({kRender + " --threads " + v, 2});
    cases.push_back({kRender + " --max-depth " + v, 2});
  }
  for (const char* v : {"-1", "2147483648", "x"}) cases.push_back({kRender + " --barbules " + v, 2});
  for (const char* v : {"0", "-1", "100000"}) cases.push_back({kCompare + " --light-sequence --columns " + v, 2});
  // Floats out of their range (NaN and Inf are in the test above).
  const std::pair<std::string, std::vector<std::string>> ranges[] = {
      {"--exposure", {"65", "-65", "1e308"}},
      {"--fov", {"0", "1e-30", "180", "-5"}},
      {"--margin", {"-0.1", "11", "1e30"}},
      {"--target-error", {"0", "-1", "2"}},
      {"--env-scale", {"-1", "1e7"}},
  };
  for (const auto& [opt, values] : ranges)
    for (const auto& v : values) cases.push_back({kRender + " " + opt + " " + v, 2});
  for (const char* v : {"0", "-0.1", "1e308", "1e-320"})
    cases.push_back({"analyze {d}/photo.png -o {o}/out.json --mm-per-px " + std::string(v), 2});
  for (const char* v : {"0", "-3"}) {
    cases.push_back({"analyze {d}/photo.png -o {o}/out.json --grid-mm " + std::string(v), 2});
    cases.push_back({"analyze {d}/photo.png -o {o}/out.json --max-megapixels " + std::string(v), 2});
    cases.push_back({"analyze {d}/photo.png -o {o}/out.json --feather " + std::string(v), 2});
    cases.push_back({"photo-to-feather {d}/photo.png -o {o}/ptf --mm-per-px " + std::string(v), 2});
    cases.push_back({"photo-to-feather {d}/photo.png -o {o}/ptf --spp " + std::string(v), 2});
    cases.push_back({"photo-to-feather {d}/photo.png -o {o}/ptf --size " + std::string(v), 2});
    cases.push_back({"generate --preset rock-dove-wing -o {o}/out.fcurves --preview-size " + std::string(v), 2});
  }
  cases.push_back({"generate --preset rock-dove-wing -o {o}/out.fcurves --preview-size 99999", 2});
  for (const char* v : {"-1", "17", "x", "1.5"})
    cases.push_back({"photo-to-feather {d}/photo.png -o {o}/ptf --calibrate " + std::string(v), 2});
  run_cases("usage", cases);
}

// One option model (docs/cli.md): an option several commands take refuses the same
// values in every one of them; whole numbers beyond their type are usage errors,
// not saturated; options that cannot work together are usage errors found before
// any file is read (the input named here does not exist, so reading it would be
// exit 1).
TEST_F(HostileCli, OneOptionModelInEveryCommand) {
  const std::pair<std::string, std::string> commands[] = {
      {"render", kRender},
      {"compare", kCompare},
      {"export", "export {d}/f.fcurves -o {o}/out.pbrt"},
      {"bench", "bench --csv {o}/out.csv --plot {o}/out.png"},
      {"photo-to-feather", "photo-to-feather {d}/photo.png -o {o}/ptf"},
  };
  const std::pair<std::string, std::vector<std::string>> shared[] = {
      {"--spp", {"0", "-5"}},
      {"--lights", {"bogus", "1,,2", "0", "5-2", "3,", "-3", "99999999999"}},
      {"--margin", {"-1", "11"}},
      {"--fov", {"0", "180"}},
      {"--up", {"1,2", "1,2,3,4"}},
      {"--camera-pos", {"1,2", "x,y,z"}},
      {"--env", {"-1", "1,-1,1", "1,2"}},
      {"--beta-m", {"0", "2"}},
      {"--beta-n", {"-0.5", "1.5"}},
      {"--alpha", {"46", "-90"}},
      {"--eta", {"0.5"}},
      {"--sigma-a", {"-1,0,0", "1,1"}},
      {"--max-depth", {"-1", "2000"}},
      {"--threads", {"-1", "5000"}},
      {"--backdrop", {"grey"}},
      {"--resolution", {"0x8", "8"}},
      {"--shading", {"bogus"}},
      {"--light-pick", {"bogus"}},
      {"--allocation", {"bogus"}},
  };
  std::vector<Case> cases;
  std::map<std::string, int> commands_per_option;
  for (const auto& [sub, base] : commands) {
    const auto taken = options_of_type(sub, "");
    for (const auto& [opt, values] : shared) {
      if (std::find(taken.begin(), taken.end(), opt) == taken.end()) continue;
      ++commands_per_option[opt];
      for (const auto& v : values) cases.push_back({base + " " + opt + " '" + v + "'", 2, opt});
    }
    // Whole numbers beyond their type: refused, never wrapped or saturated.
    for (const std::string& opt : options_of_type(sub, "UINT"))
      for (const char* v : {"18446744073709551616", "99999999999999999999999"})
        cases.push_back({base + " " + opt + " " + v, 2, opt});
    for (const std::string& opt : options_of_type(sub, "INT"))
      for (const char* v : {"2147483648", "-2147483649", "99999999999999999999"})
        cases.push_back({base + " " + opt + " " + v, 2, opt});
  }
  // export takes the view options render takes, with render's checks.
  for (const char* opt : {"--spp", "--lights", "--margin", "--env", "--beta-m", "--sigma-a", "--shading"})
    EXPECT_GE(commands_per_option[opt], 2) << opt << " is taken by one command only: the table lost it";

  const std::string missing = "{d}/missing.fcurves";
  const std::string render = "render " + missing + " --resolution 8x8 -o {o}/out.png";
  const std::string compare = "compare " + missing + " --resolution 8x8 -o {o}/out.png";
  const std::vector<Case> combinations = {
      {render + " --target-error 0.1", 2, "--adaptive"},
      {render + " --min-spp 4", 2, "--adaptive"},
      {render + " --env-scale 2", 2, "--env"},
      {render + " --melanin 1 --sigma-a 1,1,1", 2, "--melanin"},
      {render + " --aov structure", 2, "--shading substructure"},
      {render + " --aov structure --shading farfield", 2, "--shading substructure"},
      {render + " --lights 26", 2, "LED 26"},
      {render + " --lights 1-30", 2, "LED 30"},
      {"render " + missing + " -o {o}/out.bmp", 2, "extension"},
      {compare + " --columns 3", 2, "--light-sequence"},
      {compare + " --light-sequence --photo {d}/photo.png", 2, "--photo"},
      {"compare " + missing + " -o {o}/out.gif", 2, "extension"},
      {"export " + missing + " -o {o}/out.obj --spp 4", 2, "--spp"},
      {"export " + missing + " -o {o}/out.obj --lights 1", 2, "--lights"},
      {"export " + missing + " -o {o}/out.fcurves --env 1", 2, "--env"},
      {"export " + missing + " -o {o}/out.fcurves --beta-m 0.5", 2, "--beta-m"},
      {"export " + missing + " -o {o}/out.usd", 2, "format"},
      {"generate", 2, "--preset"},
      {"generate --seed 3", 2, "--preset"},
      {"generate --preset rock-dove-wing", 2, "-o"},
      {"generate --preset rock-dove-wing -o {o}/out.png", 2, ".fcurves"},
      {"generate --preset rock-dove-wing --preview {o}/preview.png", 2, "-o"},
      {"generate --list-presets -o {o}/out.fcurves", 2, "--list-presets"},
      {"generate --list-presets --seed 2", 2, "--list-presets"},
      {"generate --preset rock-dove-wing --feather 2 -o {o}/out.fcurves", 2, "--layout"},
      {"generate --preset rock-dove-wing --preview-size 64 -o {o}/out.fcurves", 2, "--preview"},
      {"generate --params " + missing + " -o {o}/out.fcurves --feather 1", 2, "--layout"},
      {"bench " + missing + " --csv {o}/out.csv --seed 7 --reference-seed 7", 2, "--reference-seed"},
      {"bench " + missing + " --csv {o}/out.csv --spp 1,2,x", 2, "--spp"},
      {"bench " + missing + " --csv {o}/out.csv --spp 1,,2", 2, "--spp"},
      {"bench " + missing + " --csv {o}/out.csv --spp 64 --reference-spp 128", 2, "--reference-spp"},
      {"bench " + missing + " --csv {o}/out.csv --modes hair,bogus", 2, "--modes"},
      {"bench " + missing + " --csv {o}/out.csv --zoom 1,2", 2, "--zoom"},
      {"bench " + missing + " --csv {o}/out.csv --zoom 1,2,0", 2, "--zoom"},
      {"photo-to-feather {d}/missing.png -o {o}/ptf --lights 40", 2, "LED 40"},
      {"photo-to-feather {d}/missing.png -o {o}/ptf --min-spp 4", 2, "--adaptive"},
      {"info " + missing + " --spp 4", 2, "--spp"},
      {"analyze {d}/missing.png -o {o}/out.json --spp 4", 2, "--spp"},
      {"bogus", 2, "unknown command 'bogus'; the commands are analyze, bench"},
      {"-q rendr {d}/missing.fcurves -o {o}/out.png", 2, "unknown command 'rendr'"},
      {"render --bogus", 2, "unknown option --bogus"},
      {"generate --presets rock-dove-wing", 2, "--presets"},
  };
  cases.insert(cases.end(), combinations.begin(), combinations.end());
  run_cases("one_model", cases);
}

// Inputs that are missing, special files, damaged or absurd: exit 1, nothing written.
TEST_F(HostileCli, BadInputFiles) {
  std::vector<Case> cases;
  const char* curve_inputs[] = {"missing.fcurves", "dir",          "fifo.fcurves", "empty.fcurves",
                                "garbage.fcurves", "half.fcurves", "binary.fcurves", "nul.fcurves",
                                "photo.png"};
  for (const char* in : curve_inputs) {
    const std::string file = std::string("{d}/") + in;
    cases.push_back({"render " + file + " --resolution 8x8 --spp 1 -o {o}/out.png", 1});
    cases.push_back({"compare " + file + " --resolution 8x8 --spp 1 -o {o}/out.png", 1});
    cases.push_back({"export " + file + " -o {o}/out.pbrt", 1});
    cases.push_back({"info " + file, 1});
  }
  for (const char* in : {"empty.fscene", "garbage.fscene", "half.fscene", "binary.fscene", "nul.fscene", "shear.fscene",
                         "to_missing.fscene", "to_garbage.fscene", "to_fifo.fscene", "to_dev.fscene", "to_dir.fscene"}) {
    cases.push_back({"render {d}/" + std::string(in) + " --resolution 8x8 --spp 1 -o {o}/out.png", 1});
    cases.push_back({"info {d}/" + std::string(in), 1});
  }
  cases.push_back({"render {d}/to_far.fscene --resolution 8x8 --spp 1 -o {o}/out.png", 1});
  for (const char* dev : {"/dev/zero", "/dev/null", "/dev/urandom"}) {
    cases.push_back({"render " + std::string(dev) + " --resolution 8x8 --spp 1 -o {o}/out.png", 1});
    cases.push_back({"info " + std::string(dev), 1});
  }
  // The far coordinate, the texture files and the barbule count are found later, but before any output.
  cases.push_back({"render {d}/far.fcurves --resolution 8x8 --spp 1 -o {o}/out.png", 1});
  cases.push_back({"compare {d}/far.fcurves --resolution 8x8 --spp 1 -o {o}/out.png", 1});
  for (const char* t : {"tex_huge", "tex_dev", "tex_fifo", "tex_missing", "tex_text", "tex_trunc"}) {
    cases.push_back({"render {d}/" + std::string(t) + ".fcurves --resolution 8x8 --spp 1 -o {o}/out.png", 1});
    cases.push_back({"compare {d}/" + std::string(t) + ".fcurves --resolution 8x8 --spp 1 -o {o}/out.png", 1});
  }
  cases.push_back({"render {d}/many_barbules.fcurves --shading explicit --resolution 8x8 --spp 1 -o {o}/out.png", 1});
  // Beyond the format's range: refused as a usage error when the command line is read.
  cases.push_back({kRender + " --shading explicit --barbules 2000000000 --barbule-radius 0.001 --ramus-radius 0.01 "
                             "--ribbon-width 0.1",
                   2});
  // Images: the photo of analyze and photo-to-feather, compare's --photo, render's --env.
  const char* images[] = {"missing.png", "dir",       "fifo.png", "empty.png", "text.png", "trunc.png",
                          "trunc.jpg",   "huge.png",  "wide.png", "zero.png",  "f.fcurves"};
  for (const char* img : images) {
    const std::string file = std::string("{d}/") + img;
    cases.push_back({"analyze " + file + " -o {o}/out.json --overlay {o}/overlay.png", 1});
    cases.push_back({kCompare + " --photo " + file, 1});
    cases.push_back({kRender + " --env " + file, 1});
    cases.push_back({"photo-to-feather " + file + " -o {o}/ptf", 1});
  }
  for (const char* dev : {"/dev/zero", "/dev/null"}) {
    cases.push_back({"analyze " + std::string(dev) + " -o {o}/out.json", 1});
    cases.push_back({kCompare + " --photo " + dev, 1});
    cases.push_back({kRender + " --env " + dev, 1});
  }
  cases.push_back({"analyze {d}/small.png -o {o}/out.json", 1});
  // Parameters, layouts and rigs.
  for (const char* p : {"missing.json", "dir", "fifo", "empty.json", "notjson.json", "array.json", "bad.json", "deep.json",
                        "inf.json", "photo.png"}) {
    const std::string file = std::string("{d}/") + p;
    cases.push_back({"generate --params " + file + " -o {o}/out.fcurves --preview {o}/preview.png", 1});
    cases.push_back({"generate --layout " + file + " -o {o}/out.fcurves --preview {o}/preview.png", 1});
    cases.push_back({kRender + " --rig " + file, 1});
  }
  cases.push_back({"generate --preset no-such-bird -o {o}/out.fcurves", 1});
  if (have_layout_) {
    for (const char* l : {"layout_trunc.json", "layout_noalbedo.json", "layout_huge_albedo.json", "layout_dev_albedo.json"})
      cases.push_back({"generate --layout {d}/" + std::string(l) + " -o {o}/out.fcurves --preview {o}/preview.png", 1});
    cases.push_back({"generate --layout {d}/layout.json --feather 9 -o {o}/out.fcurves", 1});
  }
  for (const char* v : {"0,0,0", "1,2", "nan,0,0", "1e39,0,0", "a,b,c", "1,2,3,4"}) {
    cases.push_back({kRender + " --up " + std::string(v), v == std::string("0,0,0") ? 1 : 2});
    if (v != std::string("0,0,0")) cases.push_back({kRender + " --camera-pos " + std::string(v), 2});
  }
  cases.push_back({kRender + " --camera-pos 0,0,100 --look-at 0,0,100", 1});
  cases.push_back({kRender + " --up 0,0,1", 1});  // parallel to the default top view
  for (const char* v : {"1,2,3", "nan,1,1,1", "1,1,1,inf", "1,2,3,4,"})
    cases.push_back({kRender + " --directional " + std::string(v), 2});
  for (const char* v : {"-1", "nan", "1,2,3", "x"}) cases.push_back({kRender + " --melanin " + std::string(v), 2});
  for (const char* v : {"1,2", "nan,0,0", "-1,0,0"}) cases.push_back({kRender + " --sigma-a " + std::string(v), 2});
  // The material's values and an LED the rig lacks: usage errors (docs/cli.md, "One option model").
  for (const char* v : {"2", "0", "-1"}) cases.push_back({kRender + " --beta-m " + std::string(v), 2});
  cases.push_back({kRender + " --eta 0.5", 2});
  cases.push_back({kRender + " --lights 26", 2});
  cases.push_back({kCompare + " --barbule-elevation 0", 2});  // the library's range, checked at parse time
  cases.push_back({kRender + " --aov structure", 2});  // needs substructure shading: a usage error
  run_cases("inputs", cases);
}

// Outputs that cannot be written, or would collide: exit 1 (2 for a usage error),
// and every output that was there before is left as it was, across all of a
// command's outputs.
TEST_F(HostileCli, OutputsAllOrNone) {
  std::vector<Case> cases = {
      {"render {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/nodir/out.png", 1},
      // An output whose name picks no format: a usage error, before anything is read.
      {"render {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/out.bmp2", 2},
      {"render {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}", 2},
      {"render {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/", 2},
      {"render {d}/f.fcurves --resolution 8x8 --spp 1 -o ''", 2, "-o is empty"},
      {"compare {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/nodir/out.png", 1},
      {"compare {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/out.txt", 2},
      {"export {d}/f.fcurves -o {o}/nodir/out.pbrt", 1},
      {"export {d}/f.fcurves --format pbrt -o {o}", 1},
      {"analyze {d}/photo.png -o {o}/nodir/out.json --overlay {o}/overlay.png --mm-per-px 0.1", 1},
      {"analyze {d}/photo.png -o {o}/out.json --overlay {o}/nodir/overlay.png --mm-per-px 0.1", 1},
      {"analyze {d}/photo.png -o {o}/out.json --overlay {o}/overlay.bogusext --mm-per-px 0.1", 1},
      // Several outputs: the curves must not be replaced when the preview fails.
      {"generate --preset rock-dove-wing -o {o}/out.fcurves --preview {o}/nodir/p.png", 1},
      {"generate --preset rock-dove-wing -o {o}/out.fcurves --preview {o}/preview.bogusext", 1},
      {"generate --preset rock-dove-wing -o {o}/out.fcurves --preview {o}", 1},
      {"generate --preset rock-dove-wing -o {o}/nodir/out.fcurves --preview {o}/preview.png", 1},
      {"generate --preset rock-dove-wing -o {o}/out.obj", 2},
      {"generate --preset rock-dove-wing -o {o}/out.fcurves --preview {o}/out.fcurves", 1},
      {"bench --csv {o}/out.csv --plot {o}/nodir/out.png --resolution 8x8 --spp 1 --reference-spp 4 --modes hair", 1},
      {"photo-to-feather {d}/photo.png -o {o}/out.png", 1},  // a file, not a folder
  };
  if (have_layout_) {
    // With --layout the albedo texture is an output too: none of the three may change.
    cases.push_back({"generate --layout {d}/layout.json -o {o}/out.fcurves --preview {o}/nodir/p.png", 1});
    cases.push_back({"generate --layout {d}/layout.json -o {o}/out.fcurves --preview {o}/preview.bogusext", 1});
    cases.push_back({"generate --layout {d}/layout.json -o {o}/nodir/out.fcurves", 1});
  }
  run_cases("outputs", cases);
}

// An output never replaces an input of its own run (by path, or the same file
// under another name), nor a FIFO or device; a file it replaces keeps its mode.
TEST_F(HostileCli, OutputsNeverReplaceInputsOrSpecialFiles) {
  const fs::path dir = root_ / "clobber";
  fs::create_directories(dir);
  fs::copy_file(in_ / "photo.png", dir / "p.png", fs::copy_options::overwrite_existing);
  fs::copy_file(in_ / "f.fcurves", dir / "f.fcurves", fs::copy_options::overwrite_existing);
  fs::remove(dir / "alias.png");
  fs::create_hard_link(dir / "f.fcurves", dir / "alias.png");  // the curve file under an image's name
  const std::string photo = read_file(dir / "p.png"), curves = read_file(dir / "f.fcurves");
  const std::string q = "'" + dir.string() + "/";
  struct Refusal {
    std::string args, mention;
  };
  const std::vector<Refusal> refused = {
      {"analyze " + q + "p.png' -o " + q + "p.png' --mm-per-px 0.1", "is an input of this command"},
      {"analyze " + q + "p.png' -o " + q + "out.json' --overlay " + q + "p.png' --mm-per-px 0.1",
       "is an input of this command"},
      {"render " + q + "f.fcurves' --resolution 8x8 --spp 1 -o " + q + "alias.png'", "is an input of this command"},
  };
  for (const Refusal& r : refused) {
    const test::CliStreams out = test::plumage_cli_streams("-q " + r.args);
    EXPECT_EQ(out.rc, 1) << r.args << ": " << out.err;
    EXPECT_NE(out.err.find(r.mention), std::string::npos) << r.args << ": " << out.err;
    EXPECT_EQ(std::count(out.err.begin(), out.err.end(), '\n'), 1) << out.err;
    EXPECT_EQ(read_file(dir / "p.png"), photo) << r.args;
    EXPECT_EQ(read_file(dir / "f.fcurves"), curves) << r.args;
  }
  // A FIFO named as the output stays a FIFO (the run would have replaced it with a file).
  const fs::path fifo = dir / "fifo.png";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const test::CliStreams f =
      test::plumage_cli_streams("-q render " + q + "f.fcurves' --resolution 8x8 --spp 1 -o '" + fifo.string() + "'");
  EXPECT_EQ(f.rc, 1) << f.err;
  EXPECT_NE(f.err.find("not a regular file"), std::string::npos) << f.err;
  EXPECT_TRUE(fs::is_fifo(fifo));
  // A private output stays private when it is written again.
  const fs::path priv = dir / "private.png";
  const std::string render = "-q render " + q + "f.fcurves' --resolution 8x8 --spp 1 -o '" + priv.string() + "'";
  ASSERT_EQ(test::plumage_cli_streams(render).rc, 0);
  fs::permissions(priv, fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::replace);
  ASSERT_EQ(test::plumage_cli_streams(render).rc, 0);
  EXPECT_EQ(fs::status(priv).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
  // No temporaries left.
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// What a command prints to stdout must arrive: a full device or a closed stdout
// is a one-line error and exit 1, not exit 0 with the output lost.
TEST_F(HostileCli, WritesToStdoutAreChecked) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string f = "'" + (in_ / "f.fcurves").string() + "'";
  for (const std::string& args : {"info " + f, "info --json " + f, std::string("generate --print-params --preset rock-dove-wing"),
                                  std::string("generate --list-presets"), std::string("--help")}) {
    for (const char* sink : {" >/dev/full", " >&-"}) {
      const test::CliStreams r = test::plumage_cli_streams(args + sink);
      EXPECT_EQ(r.rc, 1) << args << sink << ": " << r.err;
      EXPECT_EQ(r.err.rfind("plumage: error: cannot write to standard output: ", 0), 0u) << args << sink << ": " << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << sink << ": " << r.err;
    }
  }
  EXPECT_EQ(test::plumage_cli_streams("info " + f + " >/dev/null").rc, 0);
}

// The error names the real culprit, not a symptom further down the line.
TEST_F(HostileCli, MessagesNameTheRealCulprit) {
  const std::vector<Case> cases = {
      {"render {d}/far.fcurves --resolution 8x8 --spp 1 -o {o}/out.png", 1, "bounding box"},
      {kRender + " --fov 1e-30", 2, "--fov: '1e-30' is outside [0.01, 179]"},
      {kRender + " --margin nan", 2, "--margin: 'nan' is not a finite number"},
      {kRender + " --exposure 1e308", 2, "--exposure: '1e308' is outside [-64, 64]"},
      {"analyze {d}/photo.png -o {o}/out.json --mm-per-px 0", 2, "--mm-per-px: '0' is outside [0.0001, 1000]"},
      {"analyze {d}/trunc.jpg -o {o}/out.json", 1, "the JPEG file is cut short"},
      {"analyze {d}/trunc.png -o {o}/out.json", 1, "the PNG file is cut short"},
      {kRender + " --seed -1", 2, "--seed: '-1' is negative"},
      {kRender + " --shading Hair", 2, "--shading: 'Hair' is not one of: hair, substructure, explicit"},
      {kRender + " --resolution 65536x65536", 2, "4294.967296 megapixels; the limit is 16384 pixels a side and 64 megapixels"},
      {"render {d}/many_barbules.fcurves --shading explicit --resolution 8x8 --spp 1 -o {o}/out.png", 1,
       "above its 8 GiB ceiling; lower the barbule count (--barbules)"},
      {"render {d}/tex_huge.fcurves --resolution 8x8 --spp 1 -o {o}/out.png", 1,
       "20000x20000x3 (400 megapixels), above the 128-megapixel limit"},
      {kRender + " --env /dev/zero", 1, "/dev/zero: is not a regular file"},
      {kRender + " --env nan", 2, "--env: 'nan' is neither a grey value nor R,G,B of finite numbers"},
      {kRender + " --env 1,2", 2, "--env: '1,2' is neither a grey value nor R,G,B of finite numbers"},
      {kRender + " --env 0.5,inf,1", 2, "--env: '0.5,inf,1' is neither a grey value nor R,G,B"},
      {kCompare + " --photo {d}/fifo.png", 1, "{d}/fifo.png: is not a regular file"},
      {kRender + " --env {d}/zero.png", 1, "Invalid IHDR data"},  // libpng's words, inside the one line
      {"generate --preset rock-dove-wing -o {o}/out.fcurves --preview {o}/nodir/p.png", 1, "does not exist"},
      // Values each in range whose product is not: the options named, not the library's internals.
      {kRender + " --env 3e38 --env-scale 1e6", 2, "--env 3e38 times --env-scale 1e+06 is beyond"},
      {kRender + " --melanin 3e38", 2, "--melanin 3e38 gives an absorption beyond the largest float"},
      {kRender + " --directional 0,0,0,1", 2, "--directional 0,0,0,1: the direction must not be zero"},
      // A camera beyond 1e18 mm: an error, not Embree's assertion (it aborted the run).
      {kRender + " --look-at 3e38,3e38,0", 1, "--camera-pos/--look-at are too far out"},
      {kRender + " --camera-pos 1e19,0,0", 1, "--camera-pos/--look-at are too far out"},
      {"bench --csv '' --resolution 8x8 --spp 1 --reference-spp 4", 2, "--csv is empty"},
  };
  run_cases("messages", cases);
}

// Valid but unusual runs succeed and write finite images.
TEST_F(HostileCli, EdgeValuesThatAreAllowedRenderFiniteImages) {
  std::vector<Case> cases = {
      {kRender + " --exposure 64", 0},
      {kRender + " --exposure -64", 0},
      {kRender + " --fov 0.01", 0},
      {kRender + " --fov 179", 0},
      {kRender + " --margin 10", 0},
      {kRender + " --margin 0", 0},
      {"render {d}/f.fcurves --resolution 1x1 --spp 1 -o {o}/out.png", 0},
      {"render {d}/f.fcurves --resolution 64x1 --spp 1 -o {o}/out.png", 0},
      {kRender + " --threads 4096", 0},
      {kRender + " --max-depth 0", 0},
      {kRender + " --seed 18446744073709551615", 0},
      {kRender + " --env 1e6 --env-scale 1e6", 0},
      {kRender + " --env {d}/small.png", 0},
      {kRender + " --directional 0,0,1,1e30", 0},
      {kRender + " --directional 1e30,1e30,1e30,1", 0},  // its length would overflow a float
      {kRender + " --look-at 1e18,0,0", 0},
      {"render {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/out.exr --directional 0,0,1,3e38 --exposure 64", 0},
      {kRender + " --sigma-a 1e30,0,1e-30", 0},
      {kRender + " --projection orthographic --lights none --env 1", 0},
      {kRender + " --shading substructure --barbules 0", 0},
      {kRender + " --shading explicit --barbules 3", 0},
      {"render {d}/f.fcurves --resolution 8x8 --spp 1 -o {o}/out.exr --exposure 64", 0},
      {kCompare + " --photo {d}/small.png", 0},
      {"generate --preset rock-dove-wing -o {o}/out.fcurves --preview {o}/preview.png --preview-size 16", 0},
  };
  run_cases("edges", cases);
}

}  // namespace
