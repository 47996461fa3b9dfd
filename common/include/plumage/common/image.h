#pragma once
// The one image type and the one image reader/writer of Plumage. PNG (libpng)
// and OpenEXR (OpenEXR) are read and written in the process; every other format
// goes through OpenImageIO in a module, plumage_image_oiio.so, that is loaded
// the first time such a file is met (docs/robustness.md, "Images").
// Pixels are linear float, row-major, top row first, interleaved channels.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace plumage {

// Rec. 709 / sRGB luminance of a linear RGB colour, and its weights for loops
// over separate channel arrays.
inline constexpr float kLumR = 0.2126f, kLumG = 0.7152f, kLumB = 0.0722f;
inline float luminance(const glm::vec3& c) { return kLumR * c.x + kLumG * c.y + kLumB * c.z; }

class FileBatch;

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
      : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c, fill) {}
  float* at(int x, int y) { return &pixels[(std::size_t(y) * width + x) * channels]; }
  const float* at(int x, int y) const { return &pixels[(std::size_t(y) * width + x) * channels]; }
  glm::vec3 rgb(int x, int y) const;        // channels 0..2 (grey replicated)
  void set_rgb(int x, int y, const glm::vec3& c);
  bool empty() const { return pixels.empty(); }
};

float srgb_to_linear(float v);
float linear_to_srgb(float v);

// Writes atomically. The extension picks the format: .exr (linear float, as is,
// ZIP-compressed), .hdr (linear), anything else (.png, .jpg, .tif, ...) is 8-bit
// with the sRGB transfer curve applied to colour channels (alpha, the last of 2
// or 4 channels, stays linear), clamped to [0,1]. `jpeg_quality` (1-100; 0: 98)
// is used by JPEG only; a JPEG (.jpg, .jpeg) holds grey or RGB, so the alpha of
// 2 or 4 channels is left out of it.
void write_image(const std::filesystem::path& path, const Image& img, int jpeg_quality = 0);
// The same, staged in `batch` (atomic_file.h) with a command's other outputs.
void write_image(FileBatch& batch, const std::filesystem::path& path, const Image& img, int jpeg_quality = 0);

// Neither function premultiplies or un-premultiplies alpha: what is written is
// what is read back (PNG stores straight alpha, so pass straight alpha for PNG).

// Why a PNG, JPEG or OpenEXR file is damaged, or "" when it looks whole (other
// formats: ""): a PNG without its IEND chunk, a JPEG without the end-of-image
// marker after its last scan (decoders would return a partly grey image and
// print their own warning), an EXR header whose attribute sizes run past the
// end of the file or whose data window is absurd (OpenEXR would allocate that
// much while opening it, before any size check of ours).
std::string damage_of(const std::filesystem::path& path);

// The largest image read_image decodes: 128 megapixels (a 16384x8192 environment
// map). Its size is read from the header first, so a larger one is refused before
// any pixel memory is taken (up to 2 GiB of float pixels at 4 channels).
inline constexpr double kMaxImageMegapixels = 128.0;

// The longest side and the most channels read_image accepts. Decoders take
// scratch memory per block of scanlines (OpenEXR's DWAB blocks hold 256 of them),
// so a 1441796x1 EXR inside the megapixel limit made OpenImageIO ask for 4.4 GB
// (found by fuzz_image). With these caps a block needs at most
// 256 x 32768 x 16 x 4 bytes = 512 MiB.
inline constexpr int kMaxImageSide = 32768;
inline constexpr int kMaxImageChannels = 16;

// Reads PNG, OpenEXR and any format OpenImageIO knows, told apart by the file's
// first bytes. 8/16-bit integer files are taken to be sRGB and
// converted to linear unless `linearize` is false; float files are returned as is.
// Only regular files are read (check_input_file); images above `max_megapixels`,
// kMaxImageSide or kMaxImageChannels are refused unread. A float file's samples are
// made finite (ImageSource::replaced). Throws plumage::Error naming
// the file and the problem.
// What a file held besides its pixels, for a reader that needs to know.
struct ImageSource {
  int bits = 8;           // bits per sample as stored (8, 16, 32)
  bool is_float = false;  // float or half samples, returned as stored
  int alpha = -1;         // the alpha channel's index, or -1
  // Samples of a float file that were NaN or infinite, read as 0 (NaN) or the
  // image's largest (+Inf) or smallest (-Inf) finite sample; read_image also says
  // so in one warning line on stderr.
  std::size_t replaced = 0;
};
Image read_image(const std::filesystem::path& path, bool linearize = true,
                 double max_megapixels = kMaxImageMegapixels, ImageSource* source = nullptr);

}  // namespace plumage
