#pragma once
// The decoders and encoders behind read_image and write_image (image.h): PNG
// through libpng, OpenEXR through the OpenEXR library and JPEG through libjpeg
// (grey and RGB; CMYK and YCCK are read by the module), all linked into the
// process; every other format through OpenImageIO, which lives in a module
// loaded on first use (image_module.cpp) so that a process that reads and
// writes only PNG, EXR and JPEG never loads it. Private to common/.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "plumage/common/image.h"

namespace plumage::codec {

// What a file's header says, known before any pixel memory is taken.
struct Header {
  int width = 0, height = 0, channels = 0;
  int alpha = -1;         // the alpha channel's index, or -1
  bool is_float = false;  // float, half or double samples (never sRGB-decoded)
  int bits = 8;           // bits per sample as stored
};

// Called with the header before pixels are decoded; throws to refuse the image.
using HeaderCheck = std::function<void(const Header&)>;

// 8-bit samples, interleaved, as an image of code / 255 (the readers' common last step).
inline Image from_8bit(int width, int height, int channels, const std::vector<unsigned char>& data) {
  Image img(width, height, channels);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(data[i]) * (1.0f / 255.0f);
  return img;
}

// Each reader returns samples as float: integer samples as code / (2^bits - 1),
// float samples as stored; alpha as stored (straight). Errors are plumage::Error
// naming `path`.
Image read_png(const std::filesystem::path& path, const HeaderCheck& check, Header& header);
Image read_exr(const std::filesystem::path& path, const HeaderCheck& check, Header& header);
// Grey and RGB JPEG through libjpeg; CMYK and YCCK through read_with_module.
Image read_jpeg(const std::filesystem::path& path, const HeaderCheck& check, Header& header);
Image read_with_module(const std::filesystem::path& path, const HeaderCheck& check, Header& header);

// Each writer writes `file` (a temporary name); errors name `target`.
// 8-bit samples, interleaved, img.channels of them per pixel (1 to 4).
void write_png(const std::filesystem::path& file, const std::filesystem::path& target, int width, int height,
               int channels, const std::vector<unsigned char>& bytes);
// Float samples, ZIP-compressed, channels named as OpenImageIO names them (Y; R G;
// R G B; R G B A; then channel4, channel5, ...).
void write_exr(const std::filesystem::path& file, const std::filesystem::path& target, const Image& img);
// 8-bit samples as write_png takes them, 1 to 4 channels; a JPEG holds grey or
// RGB, so the alpha of 2 or 4 channels is left out. `quality` 1-100, 0 for
// kDefaultJpegQuality; 4:2:0 chroma, as libjpeg's defaults.
inline constexpr int kDefaultJpegQuality = 98;
void write_jpeg(const std::filesystem::path& file, const std::filesystem::path& target, int width, int height,
                int channels, const std::vector<unsigned char>& bytes, int quality);
// Any other format OpenImageIO writes, chosen by `format` (the target's extension
// without its dot); `samples` are float when `is_float`, else 8-bit. `quality`
// (1-100, 0 for the writer's default) is the JPEG quality.
void write_with_module(const std::filesystem::path& file, const std::filesystem::path& target,
                       const std::string& format, int width, int height, int channels, bool is_float,
                       const void* samples, int quality);

}  // namespace plumage::codec
