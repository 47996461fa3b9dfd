// The OpenImageIO module: every image format but PNG and OpenEXR (JPEG, TIFF,
// HDR, ...), for read_image and write_image (common/src/image_module.cpp). It
// is a separate shared object so that OpenImageIO, which pulls in some 260
// libraries and costs 0.15-0.2 s to load, is loaded only by a process that
// meets such a file (docs/perf/render.md).
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <memory>
#include <string>

#include "../src/image_module_abi.h"

namespace {
void put(char* error, std::size_t size, const std::string& text) {
  if (size > 0) std::snprintf(error, size, "%s", text.c_str());
}

void* open_image(const char* path, PlumageImageHeader* header, char* error, std::size_t error_size) {
  // Alpha comes back as stored: no premultiplication on read.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    put(error, error_size, OIIO::geterror());
    return nullptr;
  }
  const OIIO::ImageSpec& spec = in->spec();
  header->width = spec.width;
  header->height = spec.height;
  header->channels = spec.nchannels;
  header->alpha = spec.alpha_channel;
  const auto base = spec.format.basetype;
  header->is_float =
      base == OIIO::TypeDesc::FLOAT || base == OIIO::TypeDesc::HALF || base == OIIO::TypeDesc::DOUBLE;
  header->bits = int(spec.format.size()) * 8;
  return in.release();
}

int read_image(void* handle, float* pixels, char* error, std::size_t error_size) {
  auto* in = static_cast<OIIO::ImageInput*>(handle);
  if (in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT, pixels)) return 1;
  put(error, error_size, in->geterror());
  return 0;
}

void close_image(void* handle) {
  std::unique_ptr<OIIO::ImageInput> in(static_cast<OIIO::ImageInput*>(handle));
  in->close();
}

int write_image(const char* file, const char* format, int width, int height, int channels, int is_float,
                const void* samples, int quality, char* error, std::size_t error_size) {
  auto out = OIIO::ImageOutput::create(format);
  if (!out) {
    put(error, error_size, "no image writer for extension '." + std::string(format) + "': " + OIIO::geterror());
    return 0;
  }
  const OIIO::TypeDesc type = is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(width, height, channels, type);
  // Pixels go to the file as given: without this OIIO divides colour by alpha.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (quality > 0) {
    spec.attribute("Compression", "jpeg:" + std::to_string(quality));
    spec.attribute("CompressionQuality", quality);
  }
  if (!out->open(file, spec) || !out->write_image(type, samples) || !out->close()) {
    put(error, error_size, out->geterror());
    return 0;
  }
  return 1;
}

const PlumageImageModule kModule = {plumage::codec::kImageModuleAbi, open_image, read_image, close_image, write_image};
}  // namespace

extern "C" __attribute__((visibility("default"))) const PlumageImageModule* plumage_image_module_v1() { return &kModule; }
