// Image I/O (image.h): round trips through files, the sRGB transfer curve, and
// bad input that must end in a plumage::Error naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "image_codecs.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

// A fresh directory per test, removed afterwards.
class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("plumage_image_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

Image random_image(int w, int h, int c, float lo, float hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  Image img(w, h, c);
  for (float& v : img.pixels) v = u(rng);
  return img;
}

// The reference sRGB encoding (IEC 61966-2-1), in double, independent of image.cpp.
double srgb_encode(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

void expect_error_naming(const fs::path& file, const std::function<void()>& action) {
  try {
    action();
    ADD_FAILURE() << "no error for " << file;
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, file.string()) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a plumage::Error: " << e.what();
  }
}

}  // namespace

TEST(Srgb, TransferFunctionsAreInverse) {
  for (int i = 0; i <= 100000; ++i) {
    const float v = i / 100000.0f;
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(v)), v, 2e-6f) << v;
    EXPECT_NEAR(srgb_to_linear(linear_to_srgb(v)), v, 2e-6f) << v;
  }
}

TEST(Srgb, MatchesTheStandardCurve) {
  // Spot values of IEC 61966-2-1 and the branch point, from the formula in double.
  for (float v : {0.0f, 0.001f, 0.0031308f, 0.0032f, 0.04f, 0.18f, 0.5f, 0.99f, 1.0f})
    EXPECT_NEAR(linear_to_srgb(v), srgb_encode(v), 1e-6) << v;
  EXPECT_NEAR(linear_to_srgb(0.18f), 0.4614f, 1e-4f);  // middle grey
  EXPECT_EQ(linear_to_srgb(std::nanf("")), 0.0f);
  EXPECT_EQ(linear_to_srgb(-1.0f), 0.0f);
  // Monotone across the linear/power branch point.
  float prev = -1;
  for (int i = 0; i <= 10000; ++i) {
    const float s = linear_to_srgb(i * 1e-6f);
    EXPECT_GE(s, prev);
    prev = s;
  }
}

TEST_F(ImageFiles, PngRoundTripWithinOneQuantisationStep) {
  for (int channels : {1, 3, 4}) {
    const Image img = random_image(37, 23, channels, -0.1f, 1.1f, 7 + channels);
    const fs::path f = dir_ / ("rt" + std::to_string(channels) + ".png");
    write_image(f, img);
    const Image back = read_image(f);
    ASSERT_EQ(back.width, img.width);
    ASSERT_EQ(back.height, img.height);
    ASSERT_EQ(back.channels, img.channels);
    const int alpha = channels == 4 ? 3 : -1;
    for (std::size_t i = 0; i < img.pixels.size(); ++i) {
      const bool is_alpha = int(i % channels) == alpha;
      // Compared where the file stores them: sRGB-encoded colour, linear alpha, in [0,1].
      const double want =
          is_alpha ? std::clamp(double(img.pixels[i]), 0.0, 1.0) : srgb_encode(img.pixels[i]);
      const double got = is_alpha ? back.pixels[i] : srgb_encode(back.pixels[i]);
      ASSERT_NEAR(got, want, 0.5 / 255 + 1e-5) << "channels=" << channels << " i=" << i;
    }
  }
}

TEST_F(ImageFiles, PngCodesAreLinearToSrgbRoundedAndBackIsSrgbToLinear) {
  // The writer's codes without a pow per value must be exactly
  // lround(clamp(linear_to_srgb(v), 0, 1) * 255), and the reader's remembered
  // decode exactly srgb_to_linear(code / 255): a dense sweep over [-0.1, 1.2],
  // every code's boundary (the least float with that code) and the float below
  // it, NaN and infinities.
  const auto code = [](float v) { return long(std::lround(std::clamp(linear_to_srgb(v), 0.0f, 1.0f) * 255.0f)); };
  std::vector<float> values;
  for (int i = 0; i <= 1300000; ++i) values.push_back(-0.1f + 1.3f * float(i) / 1300000.0f);
  for (long k = 1; k <= 255; ++k) {
    std::uint32_t lo = 0, hi = 0x7f800000u;
    while (lo < hi) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      float v;
      std::memcpy(&v, &mid, sizeof v);
      if (code(v) >= k) hi = mid; else lo = mid + 1;
    }
    float b;
    std::memcpy(&b, &lo, sizeof b);
    values.push_back(b);
    values.push_back(std::nextafter(b, 0.0f));
  }
  for (float v : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::denorm_min(), 0.0f, -0.0f})
    values.push_back(v);
  const int w = 1024, h = int((values.size() + w - 1) / w);
  Image img(w, h, 1, 0.0f);
  std::copy(values.begin(), values.end(), img.pixels.begin());
  const fs::path f = dir_ / "codes.png";
  write_image(f, img);
  const Image raw = read_image(f, false);
  const Image linear = read_image(f);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    ASSERT_EQ(std::lround(raw.pixels[i] * 255.0f), code(img.pixels[i])) << "value " << img.pixels[i];
    ASSERT_EQ(linear.pixels[i], srgb_to_linear(raw.pixels[i])) << "value " << img.pixels[i];
  }
}

TEST_F(ImageFiles, PngAlphaCodesAreLinearRounded) {
  // The alpha channel is written linear, exactly lround(clamp(v, 0, 1) * 255): a
  // dense sweep, each half-way point k + 0.5 over 255 with its float neighbours, and
  // the extremes.
  std::vector<float> values;
  for (int i = 0; i <= 400000; ++i) values.push_back(-0.1f + 1.2f * float(i) / 400000.0f);
  for (int k = 0; k < 255; ++k) {
    const float half = (float(k) + 0.5f) / 255.0f;
    for (float v = std::nextafter(std::nextafter(half, 0.0f), 0.0f); values.push_back(v), v < half + 1e-6f;)
      v = std::nextafter(v, 2.0f);
  }
  for (float v : {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                  std::numeric_limits<float>::denorm_min(), 0.0f, -0.0f, 1.0f, std::nextafter(1.0f, 0.0f)})
    values.push_back(v);
  const int w = 1024, h = int((values.size() + w - 1) / w);
  Image img(w, h, 2, 0.5f);
  for (std::size_t i = 0; i < values.size(); ++i) img.pixels[2 * i + 1] = values[i];
  const fs::path f = dir_ / "alpha.png";
  write_image(f, img);
  const Image raw = read_image(f, false);
  ASSERT_EQ(raw.channels, 2);
  for (std::size_t i = 0; i < values.size(); ++i)
    ASSERT_EQ(std::lround(raw.pixels[2 * i + 1] * 255.0f), std::lround(std::clamp(values[i], 0.0f, 1.0f) * 255.0f))
        << "alpha " << values[i];
}

TEST_F(ImageFiles, PngKeepsRowOrderAndChannels) {
  Image img(4, 3, 3, 0.0f);
  img.set_rgb(0, 0, {1, 0, 0});  // top-left red
  img.set_rgb(3, 2, {0, 0, 1});  // bottom-right blue
  const fs::path f = dir_ / "order.png";
  write_image(f, img);
  const Image back = read_image(f);
  EXPECT_EQ(back.rgb(0, 0), glm::vec3(1, 0, 0));
  EXPECT_EQ(back.rgb(3, 2), glm::vec3(0, 0, 1));
  EXPECT_EQ(back.rgb(1, 1), glm::vec3(0));
  // Without linearisation the 8-bit codes come back as code/255.
  const Image raw = read_image(f, false);
  EXPECT_EQ(raw.rgb(0, 0), glm::vec3(1, 0, 0));
}

TEST_F(ImageFiles, ExrRoundTripIsBitExact) {
  for (int channels : {1, 3, 4}) {
    Image img = random_image(29, 17, channels, -5.0f, 1e4f, 20 + channels);
    img.pixels[0] = 0.0f;
    img.pixels[1] = -0.0f;
    img.pixels[2] = 1e-30f;
    img.pixels[3] = 3.4e38f;
    img.pixels[4] = std::numeric_limits<float>::denorm_min();
    const fs::path f = dir_ / ("rt" + std::to_string(channels) + ".exr");
    write_image(f, img);
    const Image back = read_image(f);
    ASSERT_EQ(back.width, img.width);
    ASSERT_EQ(back.height, img.height);
    ASSERT_EQ(back.channels, img.channels);
    ASSERT_EQ(back.pixels.size(), img.pixels.size());
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
      ASSERT_EQ(std::memcmp(&back.pixels[i], &img.pixels[i], sizeof(float)), 0)
          << "channels=" << channels << " i=" << i << ": " << back.pixels[i] << " vs "
          << img.pixels[i];
  }
}

TEST_F(ImageFiles, JpegKeepsRowOrderChannelsAndCodes) {
  // Pictures smooth in their sRGB codes and asymmetric (a transposed, flipped
  // or channel-swapped decode fails), written at quality 100 and read back,
  // both through libjpeg: every 8-bit code within a few steps of the original
  // (chroma is stored at half resolution). A JPEG holds grey or RGB: the alpha
  // of 2 or 4 channels is left out, the colour kept.
  for (int channels : {1, 2, 3, 4}) {
    Image img(48, 32, channels);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < channels; ++c)
          img.pixels[(std::size_t(y) * img.width + x) * channels + c] =
              srgb_to_linear(c == 0 ? float(x) / (img.width - 1) : c == 1 ? float(y) / (img.height - 1) : 0.25f);
    const fs::path f = dir_ / ("ramp" + std::to_string(channels) + ".jpg");
    write_image(f, img, 100);
    const Image back = read_image(f, false);
    const int colour = channels >= 3 ? 3 : 1;
    ASSERT_EQ(back.width, img.width);
    ASSERT_EQ(back.height, img.height);
    ASSERT_EQ(back.channels, colour);
    // What was written: the linear values as sRGB codes.
    double worst = 0;
    for (std::size_t p = 0; p < std::size_t(img.width) * img.height; ++p)
      for (int c = 0; c < colour; ++c)
        worst = std::max(worst, std::fabs(double(back.pixels[p * colour + c]) -
                                          srgb_encode(img.pixels[p * channels + c])) * 255);
    EXPECT_LE(worst, 6.0) << channels << " channel(s)";
  }
}

TEST_F(ImageFiles, JpegQualityIsHonouredAndDefaultsTo98) {
  // Noise is what compression throws away: at quality 20 the file is a
  // fraction of the default's, and the default writes what 98 writes.
  const Image noise = random_image(96, 64, 3, 0, 1, 11);
  write_image(dir_ / "q0.jpg", noise);
  write_image(dir_ / "q98.jpg", noise, 98);
  write_image(dir_ / "q20.jpg", noise, 20);
  EXPECT_EQ(read_file(dir_ / "q0.jpg"), read_file(dir_ / "q98.jpg"));
  EXPECT_LT(fs::file_size(dir_ / "q20.jpg") * 3, fs::file_size(dir_ / "q98.jpg"));
}

TEST_F(ImageFiles, JpegOfMoreThanFourChannelsIsRefusedAndNothingIsWritten) {
  const fs::path f = dir_ / "five.jpg";
  expect_error_naming(f, [&] { write_image(f, Image(8, 8, 5, 0.5f)); });
  EXPECT_FALSE(fs::exists(f));
  EXPECT_TRUE(fs::is_empty(dir_)) << "a temporary file was left behind";
}

TEST_F(ImageFiles, DamagedJpegIsAnErrorNamingTheFile) {
  // A JPEG header with its end-of-image marker but garbage for the rest: the
  // decoder stops with an error, never a crash or a hang.
  const fs::path good = dir_ / "good.jpg";
  write_image(good, random_image(64, 64, 3, 0, 1, 5), 90);
  std::string bytes = read_file(good);
  const std::size_t sof = bytes.find("\xff\xc0");
  ASSERT_NE(sof, std::string::npos);
  const fs::path bad = dir_ / "bad.jpg";
  std::string broken = bytes.substr(0, sof + 2) + std::string(64, '\x55') + "\xff\xda" + std::string(32, '\x00') + "\xff\xd9";
  write_file_atomic(bad, broken);
  expect_error_naming(bad, [&] { read_image(bad); });
}

TEST_F(ImageFiles, BadInputNamesTheFile) {
  const fs::path missing = dir_ / "missing.png";
  expect_error_naming(missing, [&] { read_image(missing); });

  const fs::path empty = dir_ / "empty.png";
  write_file_atomic(empty, "");
  expect_error_naming(empty, [&] { read_image(empty); });

  const fs::path text = dir_ / "notes.png";
  write_file_atomic(text, "this is not a PNG, just some text\n");
  expect_error_naming(text, [&] { read_image(text); });

  const fs::path truncated = dir_ / "truncated.png";
  write_image(truncated, random_image(64, 64, 3, 0, 1, 3));
  const std::string bytes = read_file(truncated);
  write_file_atomic(truncated, bytes.substr(0, bytes.size() / 2));
  expect_error_naming(truncated, [&] { read_image(truncated); });

  const fs::path folder = dir_ / "folder.png";
  fs::create_directories(folder);
  expect_error_naming(folder, [&] { read_image(folder); });
}

TEST_F(ImageFiles, BadWritesNameTheFileAndLeaveTheOldOneUntouched) {
  const fs::path f = dir_ / "keep.png";
  write_image(f, random_image(8, 8, 3, 0, 1, 4));
  const std::string before = read_file(f);

  Image inconsistent(8, 8, 3);
  inconsistent.pixels.resize(10);
  expect_error_naming(f, [&] { write_image(f, inconsistent); });
  expect_error_naming(f, [&] { write_image(f, Image()); });
  EXPECT_EQ(read_file(f), before);

  // An extension no writer knows: the writer fails after the temporary is made.
  const fs::path odd = dir_ / "keep.nosuchformat";
  write_file_atomic(odd, "precious");
  expect_error_naming(odd, [&] { write_image(odd, random_image(4, 4, 3, 0, 1, 5)); });
  EXPECT_EQ(read_file(odd), "precious");

  // A directory that does not exist.
  const fs::path nowhere = dir_ / "no" / "such" / "dir.png";
  expect_error_naming(nowhere, [&] { write_image(nowhere, random_image(4, 4, 3, 0, 1, 6)); });

  // No temporaries left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++files;
  EXPECT_EQ(files, 2);
}

// Finite everywhere (issue 37 item 5): a float file's NaN and infinities are read
// as finite values, counted and warned about; no writer puts one in a file.
TEST_F(ImageFiles, FloatFilesWithNaNOrInfinityAreReadFinite) {
  Image img(3, 2, 1);
  img.pixels = {0.2f, 3.0f, std::nanf(""), std::numeric_limits<float>::infinity(),
                -std::numeric_limits<float>::infinity(), -0.5f};
  const fs::path f = dir_ / "hostile.exr";
  codec::write_exr(f, f, img);  // the raw writer: write_image would make them finite first
  ImageSource source;
  const Image back = read_image(f, true, kMaxImageMegapixels, &source);
  EXPECT_EQ(source.replaced, 3u);
  const std::vector<float> expected{0.2f, 3.0f, 0.0f, 3.0f, -0.5f, -0.5f};
  ASSERT_EQ(back.pixels.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(back.pixels[i], expected[i]) << i;
  // A finite file is read as it is, and says so.
  Image fine = img;
  for (float& v : fine.pixels)
    if (!std::isfinite(v)) v = 1.0f;
  write_image(dir_ / "fine.exr", fine);
  ImageSource none;
  (void)read_image(dir_ / "fine.exr", true, kMaxImageMegapixels, &none);
  EXPECT_EQ(none.replaced, 0u);
}

TEST_F(ImageFiles, NoWriterPutsANonFiniteValueInAFile) {
  const float inf = std::numeric_limits<float>::infinity();
  for (const int channels : {3, 4}) {
    Image img = random_image(8, 6, channels, 0.0f, 2.0f, 3);
    img.pixels[0] = std::nanf("");
    img.pixels[1] = inf;
    img.pixels[2] = -inf;
    if (channels == 4) img.pixels[3] = std::nanf("");  // an alpha
    img.pixels[std::size_t(2 * channels + 1)] = inf;
    for (const std::string ext : {".exr", ".png", ".jpg", ".hdr", ".tif"}) {
      if ((ext == ".jpg" || ext == ".hdr") && channels == 4) continue;  // RGB only
      SCOPED_TRACE(ext + ", " + std::to_string(channels) + " channels");
      const fs::path f = dir_ / ("out" + std::to_string(channels) + ext);
      ASSERT_NO_THROW(write_image(f, img));
      ImageSource source;
      const Image back = read_image(f, true, kMaxImageMegapixels, &source);
      EXPECT_EQ(source.replaced, 0u) << "the file holds NaN or infinity";
      for (const float v : back.pixels) ASSERT_TRUE(std::isfinite(v));
      if (ext == ".exr") {
        EXPECT_EQ(back.pixels[0], 0.0f);
        EXPECT_EQ(back.pixels[1], std::numeric_limits<float>::max());
        EXPECT_EQ(back.pixels[2], -std::numeric_limits<float>::max());
      }
    }
  }
}

// Bounded work on hostile sizes (issue 37 item 7). A small JPEG whose header
// claims 11000 x 11000 pixels is refused from its header, before 121 megapixels
// are allocated (27 s and 1.8 GB of grey fill before); a JPEG whose scan ends
// early (cut and closed with an end-of-image marker, so its end looks whole) is
// refused at its first corrupt-data warning instead of coming back half grey.
namespace {
std::string file_bytes(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void expect_jpeg_error(const fs::path& f, const std::string& what) {
  try {
    (void)read_image(f);
    ADD_FAILURE() << "decoded " << what;
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, f.string());
    EXPECT_NE(std::string(e.what()).find("JPEG"), std::string::npos) << e.what();
  }
}
}  // namespace

TEST_F(ImageFiles, AJpegClaimingMorePixelsThanItsBytesHoldIsRefusedUndecoded) {
  const fs::path f = dir_ / "claims.jpg";
  write_image(f, random_image(64, 64, 3, 0.0f, 1.0f, 9));
  std::string bytes = file_bytes(f);
  const std::size_t sof = bytes.find("\xff\xc0");  // baseline start of frame: length, precision, height, width
  ASSERT_NE(sof, std::string::npos);
  for (const std::size_t at : {sof + 5, sof + 7}) bytes[at] = char(11000 >> 8), bytes[at + 1] = char(11000 & 0xff);
  std::ofstream(f, std::ios::binary | std::ios::trunc) << bytes;
  expect_jpeg_error(f, "a 64x64 JPEG that claims 11000x11000");
}

TEST_F(ImageFiles, AJpegWhoseScanEndsEarlyIsRefusedAtItsFirstCorruptData) {
  const fs::path f = dir_ / "short_scan.jpg";
  write_image(f, random_image(256, 256, 3, 0.0f, 1.0f, 10));
  std::string bytes = file_bytes(f);
  const std::size_t sos = bytes.rfind("\xff\xda");
  ASSERT_NE(sos, std::string::npos);
  bytes.resize(sos + (bytes.size() - sos) / 2);
  bytes += "\xff\xd9";
  std::ofstream(f, std::ios::binary | std::ios::trunc) << bytes;
  expect_jpeg_error(f, "a JPEG whose scan stops halfway");
}
