#include "plumage/common/image.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <OpenImageIO/imageio.h>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"

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
}  // namespace

void write_image(const fs::path& path, const Image& img) {
  if (img.width <= 0 || img.height <= 0 || img.channels <= 0 ||
      img.pixels.size() != std::size_t(img.width) * img.height * img.channels)
    throw Error(Location{path.string()}, "refusing to write an empty or inconsistent image");
  const std::string ext = lower_ext(path);
  const bool is_float = ext == ".exr" || ext == ".hdr";
  write_via_temp(path, [&](const fs::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw Error(Location{path.string()}, "no image writer for extension '" + ext + "': " + OIIO::geterror());
    OIIO::ImageSpec spec(img.width, img.height, img.channels, is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (ext == ".exr") spec.attribute("compression", "zip");
    // Pixels go to the file as given: without this OIIO divides colour by alpha
    // for PNG, and does so after our sRGB encoding.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!out->open(tmp.string(), spec)) throw Error(Location{path.string()}, "cannot open for writing: " + out->geterror());
    bool ok;
    if (is_float) {
      ok = out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data());
    } else {
      std::vector<unsigned char> bytes(img.pixels.size());
      const int alpha = img.channels == 4 || img.channels == 2 ? img.channels - 1 : -1;
      for (std::size_t i = 0; i < img.pixels.size(); ++i) {
        float v = img.pixels[i];
        if (int(i % img.channels) != alpha) v = linear_to_srgb(v);
        bytes[i] = static_cast<unsigned char>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
      }
      ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    }
    if (!ok || !out->close()) throw Error(Location{path.string()}, "write failed: " + out->geterror());
  });
}

Image read_image(const fs::path& path, bool linearize) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(Location{path.string()}, "no such file");
  if (fs::is_directory(path, ec)) throw Error(Location{path.string()}, "is a directory, expected an image");
  // Alpha comes back as stored (see write_image): no premultiplication on read.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) {
    std::string why = OIIO::geterror();
    throw Error(Location{path.string()}, "cannot read as an image" + (why.empty() ? std::string() : ": " + why));
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw Error(Location{path.string()}, "image has no pixels");
  Image img(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
    throw Error(Location{path.string()}, "cannot decode image: " + in->geterror());
  const bool is_float = spec.format.basetype == OIIO::TypeDesc::FLOAT || spec.format.basetype == OIIO::TypeDesc::HALF ||
                        spec.format.basetype == OIIO::TypeDesc::DOUBLE;
  in->close();
  if (linearize && !is_float) {
    const int alpha = spec.alpha_channel;
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
      if (int(i % img.channels) != alpha) img.pixels[i] = srgb_to_linear(img.pixels[i]);
  }
  return img;
}

}  // namespace plumage
