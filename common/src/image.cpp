#include "plumage/common/image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/text.h"
#include "image_codecs.h"

namespace plumage {
namespace fs = std::filesystem;

glm::vec3 Image::rgb(int x, int y) const {
  const float* p = at(x, y);
  if (channels >= 3) return {p[0], p[1], p[2]};
  return glm::vec3(p[0]);
}

void Image::set_rgb(int x, int y, const glm::vec3& c) {
  float* p = at(x, y);
  if (channels >= 3) {
    p[0] = c.x; p[1] = c.y; p[2] = c.z;
  } else {
    p[0] = (c.x + c.y + c.z) / 3.0f;
  }
}

float srgb_to_linear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float v) {
  if (!(v > 0.0f)) return 0.0f;  // also maps NaN to 0
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {
std::string lower_ext(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

// The 8-bit sRGB code of a linear value: lround(clamp(linear_to_srgb(v), 0, 1) * 255).
std::uint8_t srgb_code_reference(float v) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(linear_to_srgb(v), 0.0f, 1.0f) * 255.0f));
}

// The same code without a pow per value: every step of srgb_code_reference is
// monotone in v, so code(v) is the number of k in 1..255 whose threshold (the
// least positive float with code k or more, found once by bisection over the
// floats' bit patterns, which order positive floats) is <= v.
struct SrgbCodes {
  std::array<float, 255> threshold;
  SrgbCodes() {
    for (int k = 1; k <= 255; ++k) {
      std::uint32_t lo = 0, hi = 0x7f800000u;  // +0 ... +inf
      while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        float v;
        std::memcpy(&v, &mid, sizeof v);
        if (srgb_code_reference(v) >= k) hi = mid; else lo = mid + 1;
      }
      std::memcpy(&threshold[std::size_t(k - 1)], &lo, sizeof(float));
    }
  }
  std::uint8_t operator()(float v) const {
    if (!(v > 0.0f)) return 0;  // also NaN, as linear_to_srgb
    return static_cast<std::uint8_t>(std::upper_bound(threshold.begin(), threshold.end(), v) - threshold.begin());
  }
};

// The 8-bit samples of `img`: colour through the sRGB curve, alpha (the last of
// 2 or 4 channels) linear, both clamped to [0,1].
// NaN samples to 0, +Inf to the image's largest finite sample and -Inf to its
// smallest (0 when it has none beyond 0 that way); the count changed.
std::size_t make_finite(Image& img) {
  float largest = 0.0f, smallest = 0.0f;
  for (const float v : img.pixels)
    if (std::isfinite(v)) largest = std::max(largest, v), smallest = std::min(smallest, v);
  std::size_t replaced = 0;
  for (float& v : img.pixels) {
    if (std::isfinite(v)) continue;
    v = std::isnan(v) ? 0.0f : v > 0 ? largest : smallest;
    ++replaced;
  }
  return replaced;
}

// A copy of `img` that a float file can hold: NaN as 0, +-Inf as +-FLT_MAX.
Image finite_copy(const Image& img) {
  Image out = img;
  for (float& v : out.pixels)
    if (std::isnan(v)) v = 0.0f;
    else if (std::isinf(v)) v = v > 0 ? std::numeric_limits<float>::max() : -std::numeric_limits<float>::max();
  return out;
}

bool all_finite(const Image& img) {
  return std::all_of(img.pixels.begin(), img.pixels.end(), [](float v) { return std::isfinite(v); });
}

// lround(clamp(v, 0, 1) * 255) without a libm call (0 for NaN): x - floor(x) is
// exact for a float x in [0, 255], so the comparison with 0.5 rounds half away
// from zero as lround does.
inline unsigned char linear_byte(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  const float x = std::min(v, 1.0f) * 255.0f;
  const int k = int(x);
  return static_cast<unsigned char>(x - float(k) >= 0.5f ? k + 1 : k);
}

std::vector<unsigned char> srgb_bytes(const Image& img) {
  static const SrgbCodes srgb_code;
  std::vector<unsigned char> bytes(img.pixels.size());
  const int channels = img.channels;
  const int alpha = channels == 4 || channels == 2 ? channels - 1 : -1;
  const std::size_t pixels = img.pixels.size() / std::size_t(std::max(channels, 1));
  const float* v = img.pixels.data();
  unsigned char* out = bytes.data();
  for (std::size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < channels; ++c, ++v, ++out) {
      if (std::isnan(*v)) {  // no colour: black, and transparent
        *out = 0;
        continue;
      }
      *out = c != alpha ? srgb_code(*v) : linear_byte(*v);
    }
  return bytes;
}

// Encodes `img` into `file` (a temporary name); errors name `path`, the target.
void encode_image(const fs::path& file, const fs::path& path, const Image& img, int quality) {
  if (img.width <= 0 || img.height <= 0 || img.channels <= 0 ||
      img.pixels.size() != std::size_t(img.width) * img.height * img.channels)
    throw Error(Location{path.string()}, "refusing to write an empty or inconsistent image");
  const std::string ext = lower_ext(path);
  // No written image holds a non-finite value (a float file would keep it).
  if ((ext == ".exr" || ext == ".hdr") && !all_finite(img)) return encode_image(file, path, finite_copy(img), quality);
  if (ext == ".exr") return codec::write_exr(file, path, img);
  if (ext == ".png") return codec::write_png(file, path, img.width, img.height, img.channels, srgb_bytes(img));
  if (ext == ".jpg" || ext == ".jpeg")
    return codec::write_jpeg(file, path, img.width, img.height, img.channels, srgb_bytes(img), quality);
  const std::string format = ext.empty() ? std::string() : ext.substr(1);
  if (ext == ".hdr")
    return codec::write_with_module(file, path, format, img.width, img.height, img.channels, true, img.pixels.data(), 0);
  const std::vector<unsigned char> bytes = srgb_bytes(img);
  codec::write_with_module(file, path, format, img.width, img.height, img.channels, false, bytes.data(), quality);
}
}  // namespace

void write_image(FileBatch& batch, const fs::path& path, const Image& img, int jpeg_quality) {
  batch.stage(path, [&](const fs::path& tmp) { encode_image(tmp, path, img, jpeg_quality); });
}

void write_image(const fs::path& path, const Image& img, int jpeg_quality) {
  FileBatch batch;
  write_image(batch, path, img, jpeg_quality);
  batch.commit();
}

namespace {
std::int32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(b[at + std::size_t(k)]);
  return static_cast<std::int32_t>(v);
}

// OpenEXR's first header: attributes (name, type, int32 size, value) up to an
// empty name. Every value must lie inside the file (`file_size` bytes, of which
// `b` holds the first ones), and the data window (box2i xMin, yMin, xMax, yMax)
// must be a sane rectangle. A header that runs past `b` is left to OpenEXR.
std::string exr_header_damage(const std::string& b, std::uintmax_t file_size) {
  const bool whole = b.size() == file_size;
  std::size_t at = 8;  // magic and version
  for (int attributes = 0; attributes < 10000; ++attributes) {
    const std::size_t name_end = b.find('\0', at);
    if (name_end == std::string::npos) break;
    if (name_end == at) return {};  // the header ends
    const std::string name = b.substr(at, name_end - at);
    const std::size_t type_end = b.find('\0', name_end + 1);
    if (type_end == std::string::npos || type_end + 5 > b.size()) break;
    const std::string type = b.substr(name_end + 1, type_end - name_end - 1);
    const std::int32_t size = le32(b, type_end + 1);
    const std::size_t value = type_end + 5;
    if (size < 0 || value + std::uintmax_t(size) > file_size)
      return "the OpenEXR header is damaged (attribute '" + name + "' claims " + std::to_string(size) +
             " bytes past the end of the file)";
    if (value + std::size_t(size) > b.size()) return {};
    if (name == "dataWindow" && type == "box2i" && size == 16) {
      const std::int64_t w = std::int64_t(le32(b, value + 8)) - le32(b, value) + 1;
      const std::int64_t h = std::int64_t(le32(b, value + 12)) - le32(b, value + 4) + 1;
      if (w <= 0 || h <= 0 || w > (1 << 24) || h > (1 << 24))
        return "the OpenEXR data window is " + std::to_string(w) + "x" + std::to_string(h) + " pixels, not an image";
    }
    at = value + std::size_t(size);
  }
  return whole ? "the OpenEXR header is cut short" : std::string();
}

// `n` bytes of the file from `offset` (fewer at its end).
std::string bytes_at(const fs::path& path, std::uintmax_t offset, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(std::streamoff(offset));
  std::string b(n, '\0');
  in.read(b.data(), std::streamsize(n));
  b.resize(std::size_t(std::max<std::streamsize>(in.gcount(), 0)));
  return b;
}
}  // namespace

std::string damage_of(const fs::path& path) {
  // Only the bytes that decide are read: the first ones say the format, the last
  // ones whether the file was cut short (a 200 MB file of noise named .jpg is
  // judged by its first four bytes).
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return {};
  constexpr std::size_t kTail = 64 * 1024, kExrHeader = 16 * 1024 * 1024;
  const std::string head = bytes_at(path, 0, 8);
  const auto starts = [&](std::string_view magic) { return head.compare(0, magic.size(), magic) == 0; };
  const std::uintmax_t tail_from = size > kTail ? size - kTail : 0;
  if (starts("\x89PNG\r\n\x1a\n")) {
    // The IEND chunk closes every PNG; a few bytes may trail it.
    const std::string tail = bytes_at(path, size > 4096 ? size - 4096 : 0, 4096);
    if (tail.find("IEND") == std::string::npos) return "the PNG file is cut short (no IEND chunk at its end)";
  } else if (starts("\xff\xd8\xff")) {
    // Entropy-coded data never holds an unstuffed 0xFF 0xD9, so after the last
    // start-of-scan marker the only one is the end-of-image marker; a file cut
    // short ends in scan data (an embedded thumbnail's markers lie at its start).
    const std::string tail = bytes_at(path, tail_from, kTail);
    const std::size_t sos = tail.rfind("\xff\xda");
    if ((sos == std::string::npos && tail_from == 0) ||  // the whole file, and no scan in it
        tail.find("\xff\xd9", sos == std::string::npos ? 0 : sos) == std::string::npos)
      return "the JPEG file is cut short (no end-of-image marker after its last scan)";
  } else if (starts("\x76\x2f\x31\x01")) {
    return exr_header_damage(bytes_at(path, 0, std::size_t(std::min<std::uintmax_t>(size, kExrHeader))), size);
  }
  return {};
}

Image read_image(const fs::path& path, bool linearize, double max_megapixels, ImageSource* source) {
  const std::uintmax_t file_bytes = check_input_file(path, "an image");
  if (file_bytes == 0) throw Error(Location{path.string()}, "empty file, not an image");
  if (const std::string damage = damage_of(path); !damage.empty())
    throw Error(Location{path.string()}, damage + "; copy or export the image again");
  const Location where{path.string()};
  // The format is told by the file's first bytes, not its name.
  const std::string magic = bytes_at(path, 0, 4);
  const auto starts = [&](std::string_view m) { return magic.compare(0, m.size(), m) == 0; };
  const bool png = starts("\x89PNG"), jpeg = starts("\xff\xd8\xff"), exr = starts("\x76\x2f\x31\x01");
  const auto check = [&](const codec::Header& h) {
    if (h.width <= 0 || h.height <= 0 || h.channels <= 0) throw Error(where, "image has no pixels");
    const double megapixels = double(h.width) * double(h.height) / 1e6;
    if (megapixels > max_megapixels || h.width > kMaxImageSide || h.height > kMaxImageSide) {
      std::ostringstream m;
      m << "image is " << h.width << "x" << h.height << "x" << h.channels << " (" << std::lround(megapixels)
        << " megapixels), above the ";
      if (megapixels > max_megapixels)
        m << max_megapixels << "-megapixel limit";
      else
        m << kMaxImageSide << "-pixel limit of a side";
      m << " of image inputs; downscale it first";
      throw Error(where, m.str());
    }
    if (h.channels > kMaxImageChannels)
      throw Error(where, "image has " + std::to_string(h.channels) + " channels, above the limit of " +
                             std::to_string(kMaxImageChannels) + "; keep RGB or RGBA");
    // A file holds no more pixels than its coding packs into its bytes: JPEG needs
    // about 0.12 bit a pixel even for a flat picture (a DC difference and an
    // end-of-block code per 8x8 block), and PNG's deflate packs at most 1032:1.
    // A header claiming ten times that is a lie, refused before anything is
    // allocated or decoded (a 22 KB JPEG claiming 11000x11000 cost 1.8 GB).
    const double pixels = double(h.width) * double(h.height);
    const double least = jpeg ? pixels * 0.012 / 8 : png ? pixels * h.channels / 10320.0 : 0.0;
    if (double(file_bytes) < least)
      throw Error(where, std::string("its header claims ") + std::to_string(h.width) + "x" + std::to_string(h.height) +
                             " pixels, more than its " + std::to_string(file_bytes) + " bytes can hold (" +
                             (jpeg ? "JPEG" : "PNG") + "); the file is damaged: copy or export the image again");
  };
  codec::Header header;
  Image img = png                                              ? codec::read_png(path, check, header)
              : exr                                            ? codec::read_exr(path, check, header)
              : jpeg                                           ? codec::read_jpeg(path, check, header)
                                                               : codec::read_with_module(path, check, header);
  const bool is_float = header.is_float;
  if (source != nullptr) *source = {header.bits, header.is_float, header.alpha};
  if (is_float) {
    // No NaN or infinity goes on to a render or a comparison.
    const std::size_t replaced = make_finite(img);
    if (source != nullptr) source->replaced = replaced;
    if (replaced > 0)
      std::cerr << "plumage: warning: " << printable(path.string()) << ": " << replaced << " of "
                << img.pixels.size()
                << " samples were NaN or infinite; read as 0 (NaN) and as the image's largest (+Inf) or "
                   "smallest (-Inf) finite value\n";
  }
  if (linearize && !is_float) {
    // An 8-bit file holds at most 256 values: each is decoded once and remembered
    // by its exact float (the same result as srgb_to_linear on every sample,
    // without a pow per sample).
    std::array<float, 256> in_value, out_value;
    in_value.fill(std::numeric_limits<float>::quiet_NaN());
    const int alpha = header.alpha, channels = img.channels;
    float* v = img.pixels.data();
    const std::size_t pixels = img.pixels.size() / std::size_t(std::max(channels, 1));
    for (std::size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < channels; ++c, ++v) {
        if (c == alpha) continue;
        const std::size_t k = linear_byte(*v);  // a slot per byte value; the float itself is the key
        if (in_value[k] == *v) {
          *v = out_value[k];
          continue;
        }
        in_value[k] = *v;
        *v = out_value[k] = srgb_to_linear(*v);
      }
  }
  return img;
}

}  // namespace plumage
