// A process that reads and writes only PNG, EXR and JPEG never loads OpenImageIO
// (its ~260 libraries cost 0.15-0.25 s of every start, docs/perf/render.md,
// docs/perf/analysis.md) nor OpenCV's imgcodecs: the `plumage` binary does not
// link them; a render with an EXR sky writing EXR and PNG loads neither, nor does
// the analysis of a JPEG photo into a JPEG overlay, while a render with an HDR
// sky loads OpenImageIO through the image module (the control that shows the
// check sees a load).
#include <elf.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "plumage/common/atomic_file.h"
#include "plumage/common/image.h"

namespace fs = std::filesystem;

namespace {

// The DT_NEEDED entries of a 64-bit little-endian ELF file.
std::vector<std::string> needed_libraries(const fs::path& file) {
  const std::string b = plumage::read_file(file);
  std::vector<std::string> out;
  if (b.size() < sizeof(Elf64_Ehdr) || b.compare(0, 4, ELFMAG) != 0 || b[EI_CLASS] != ELFCLASS64) return out;
  Elf64_Ehdr eh;
  std::memcpy(&eh, b.data(), sizeof eh);
  std::vector<Elf64_Phdr> ph(eh.e_phnum);
  for (int i = 0; i < eh.e_phnum; ++i)
    std::memcpy(&ph[std::size_t(i)], b.data() + eh.e_phoff + std::size_t(i) * eh.e_phentsize, sizeof(Elf64_Phdr));
  // A virtual address to its offset in the file, through the loaded segments.
  const auto offset_of = [&](Elf64_Addr a) -> std::size_t {
    for (const Elf64_Phdr& p : ph)
      if (p.p_type == PT_LOAD && a >= p.p_vaddr && a < p.p_vaddr + p.p_filesz) return a - p.p_vaddr + p.p_offset;
    return b.size();
  };
  for (const Elf64_Phdr& p : ph) {
    if (p.p_type != PT_DYNAMIC) continue;
    std::vector<Elf64_Dyn> dyn(p.p_filesz / sizeof(Elf64_Dyn));
    std::memcpy(dyn.data(), b.data() + p.p_offset, dyn.size() * sizeof(Elf64_Dyn));
    std::size_t strtab = b.size();
    for (const Elf64_Dyn& d : dyn)
      if (d.d_tag == DT_STRTAB) strtab = offset_of(d.d_un.d_ptr);
    for (const Elf64_Dyn& d : dyn)
      if (d.d_tag == DT_NEEDED && strtab + d.d_un.d_val < b.size()) out.emplace_back(b.c_str() + strtab + d.d_un.d_val);
  }
  return out;
}

// Runs the CLI with the dynamic loader's list of what it loads (LD_DEBUG=files)
// and returns everything it printed.
std::string run_listing_loads(const std::string& args, int* rc) {
  const std::string cmd = std::string("LD_DEBUG=files '") + PLUMAGE_CLI + "' " + args + " 2>&1";
  std::string out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return "popen failed";
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  *rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

// The sanitizer build's CLI loads OpenImageIO at start (CMakeLists.txt says why).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kCliLoadsOpenImageIOAtStart = true;
#else
constexpr bool kCliLoadsOpenImageIOAtStart = false;
#endif

bool mentions(const std::vector<std::string>& libs, const std::string& part) {
  for (const std::string& l : libs)
    if (l.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(Startup, CliDoesNotLinkOpenImageIOOrImgcodecs) {
  if (kCliLoadsOpenImageIOAtStart) GTEST_SKIP() << "the sanitizer build's CLI links OpenImageIO";
  const std::vector<std::string> libs = needed_libraries(PLUMAGE_CLI);
  std::string all;
  for (const std::string& l : libs) all += l + " ";
  // The reader works: it finds what the binary must link.
  EXPECT_TRUE(mentions(libs, "libOpenEXR")) << all;
  EXPECT_TRUE(mentions(libs, "libpng")) << all;
  EXPECT_TRUE(mentions(libs, "libjpeg")) << all;
  EXPECT_TRUE(mentions(libs, "libembree")) << all;
  EXPECT_FALSE(mentions(libs, "OpenImageIO")) << all;
  EXPECT_FALSE(mentions(libs, "opencv_imgcodecs")) << all;
}

TEST(Startup, RenderLoadsOpenImageIOOnlyForOtherFormats) {
  if (kCliLoadsOpenImageIOAtStart) GTEST_SKIP() << "the sanitizer build's CLI links OpenImageIO";
  const fs::path dir = fs::temp_directory_path() / ("plumage_startup_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const plumage::Image sky(8, 4, 3, 0.8f);
  plumage::write_image(dir / "sky.exr", sky);
  plumage::write_image(dir / "sky.hdr", sky);
  int rc = -1;
  const std::string feather = (dir / "f.fcurves").string();
  run_listing_loads("-q generate --preset rock-dove-wing --seed 1 -o '" + feather + "'", &rc);
  ASSERT_EQ(rc, 0);
  const std::string render = "-q render '" + feather + "' --resolution 8x12 --spp 1 --threads 1 --lights none --env ";

  const std::string plain = run_listing_loads(
      render + "'" + (dir / "sky.exr").string() + "' -o '" + (dir / "x.exr").string() + "'", &rc);
  EXPECT_EQ(rc, 0) << plain.substr(plain.size() > 2000 ? plain.size() - 2000 : 0);
  EXPECT_NE(plain.find("libOpenEXR"), std::string::npos) << "LD_DEBUG listed no loads";
  EXPECT_EQ(plain.find("OpenImageIO"), std::string::npos);
  EXPECT_EQ(plain.find("opencv_imgcodecs"), std::string::npos);
  const std::string png = run_listing_loads(
      render + "'" + (dir / "sky.exr").string() + "' -o '" + (dir / "x.png").string() + "'", &rc);
  EXPECT_EQ(rc, 0);
  EXPECT_EQ(png.find("OpenImageIO"), std::string::npos);

  const std::string hdr = run_listing_loads(
      render + "'" + (dir / "sky.hdr").string() + "' -o '" + (dir / "y.exr").string() + "'", &rc);
  EXPECT_EQ(rc, 0);
  EXPECT_NE(hdr.find("libOpenImageIO"), std::string::npos) << "an HDR sky is read through the OpenImageIO module";
  fs::remove_all(dir);
}

TEST(Startup, AnalysingAJpegPhotoIntoAJpegOverlayDoesNotLoadOpenImageIO) {
  if (kCliLoadsOpenImageIOAtStart) GTEST_SKIP() << "the sanitizer build's CLI links OpenImageIO";
  const fs::path dir = fs::temp_directory_path() / ("plumage_startup_jpeg_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A dark ellipse on a light card, written as JPEG by this (test) process.
  plumage::Image photo(320, 200, 3, 0.9f);
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x) {
      const double u = (x - 160.0) / 120.0, v = (y - 100.0) / 30.0;
      if (u * u + v * v < 1) photo.set_rgb(x, y, {0.2f, 0.1f, 0.05f});
    }
  plumage::write_image(dir / "photo.jpg", photo, 95);
  int rc = -1;
  const std::string out = run_listing_loads("-q analyze '" + (dir / "photo.jpg").string() + "' -o '" +
                                                (dir / "photo.json").string() + "' --overlay '" +
                                                (dir / "overlay.jpg").string() + "'",
                                            &rc);
  EXPECT_EQ(rc, 0) << out.substr(out.size() > 2000 ? out.size() - 2000 : 0);
  EXPECT_NE(out.find("libjpeg"), std::string::npos) << "LD_DEBUG listed no loads";
  EXPECT_EQ(out.find("OpenImageIO"), std::string::npos) << "a JPEG photo and overlay go through libjpeg";
  EXPECT_EQ(plumage::read_image(dir / "overlay.jpg").width, photo.width);
  fs::remove_all(dir);
}
