// PNG through libpng (image_codecs.h). libpng reports errors by longjmp, so each
// call into it runs inside a frame that owns only the libpng state, kept on the
// heap; what throws (header checks, our own errors) runs after libpng returned.
#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>

#include "image_codecs.h"
#include "plumage/common/error.h"

namespace plumage::codec {
namespace fs = std::filesystem;

namespace {
// libpng's state for one file, with its error text and the jump back from it.
struct PngFile {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::FILE* file = nullptr;
  bool writing = false;
  char error[256] = {};
  std::jmp_buf jump;
  ~PngFile() {
    if (png != nullptr) {
      if (writing)
        png_destroy_write_struct(&png, info != nullptr ? &info : nullptr);
      else
        png_destroy_read_struct(&png, info != nullptr ? &info : nullptr, nullptr);
    }
    if (file != nullptr) std::fclose(file);
  }
};

[[noreturn]] void on_error(png_structp png, png_const_charp message) {
  auto* f = static_cast<PngFile*>(png_get_error_ptr(png));
  std::snprintf(f->error, sizeof f->error, "%s", message != nullptr ? message : "libpng error");
  std::longjmp(f->jump, 1);
}
// Warnings (a bad CRC in an ancillary chunk, an unknown profile) are dropped: the
// pixels libpng hands back are the answer, and stderr stays ours.
void on_warning(png_structp, png_const_charp) {}

// Reads the header, with the transformations that give 8 or 16 bits per sample:
// palette to RGB, a tRNS chunk to an alpha channel, grey below 8 bits to 8 bits,
// 16-bit samples in the machine's byte order. Returns false on a libpng error.
bool read_header(PngFile* f) {
  if (setjmp(f->jump) != 0) return false;
  png_init_io(f->png, f->file);
  // Our own limits decide (with a message that says so); libpng's default of a
  // million pixels a side would stop first with its own.
  png_set_user_limits(f->png, 0x7fffffff, 0x7fffffff);
  png_read_info(f->png, f->info);
  const int type = png_get_color_type(f->png, f->info);
  const int depth = png_get_bit_depth(f->png, f->info);
  if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(f->png);
  if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(f->png);
  if (png_get_valid(f->png, f->info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(f->png);
  if (depth == 16) png_set_swap(f->png);
  png_set_interlace_handling(f->png);
  png_read_update_info(f->png, f->info);
  return true;
}

bool read_rows(PngFile* f, png_bytepp rows) {
  if (setjmp(f->jump) != 0) return false;
  png_read_image(f->png, rows);
  png_read_end(f->png, nullptr);
  return true;
}

bool write_all(PngFile* f, int width, int height, int channels, png_bytepp rows) {
  if (setjmp(f->jump) != 0) return false;
  png_init_io(f->png, f->file);
  static const int kType[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                              PNG_COLOR_TYPE_RGB_ALPHA};
  png_set_IHDR(f->png, f->info, png_uint_32(width), png_uint_32(height), 8, kType[channels - 1],
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // zlib level 1: the artifacts are a few per cent larger than at level 6 and
  // written several times faster (docs/perf/p2f.md).
  png_set_compression_level(f->png, 1);
  png_write_info(f->png, f->info);
  png_write_image(f->png, rows);
  png_write_end(f->png, nullptr);
  return true;
}
}  // namespace

Image read_png(const fs::path& path, const HeaderCheck& check, Header& header) {
  const Location where{path.string()};
  auto f = std::make_unique<PngFile>();
  f->file = std::fopen(path.c_str(), "rb");
  if (f->file == nullptr) throw Error(where, std::string("cannot open: ") + std::strerror(errno));
  f->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, f.get(), on_error, on_warning);
  if (f->png != nullptr) f->info = png_create_info_struct(f->png);
  if (f->png == nullptr || f->info == nullptr) throw Error(where, "cannot start the PNG decoder (out of memory)");
  if (!read_header(f.get())) throw Error(where, std::string("cannot read as an image: ") + f->error);

  header.width = int(png_get_image_width(f->png, f->info));
  header.height = int(png_get_image_height(f->png, f->info));
  header.channels = png_get_channels(f->png, f->info);
  header.alpha = header.channels == 2 || header.channels == 4 ? header.channels - 1 : -1;
  header.is_float = false;
  const bool wide = png_get_bit_depth(f->png, f->info) == 16;
  header.bits = wide ? 16 : 8;
  check(header);

  const std::size_t row_bytes = png_get_rowbytes(f->png, f->info);
  const std::size_t samples = std::size_t(header.width) * header.channels;
  if (row_bytes != samples * (wide ? 2 : 1)) throw Error(where, "cannot decode image: unexpected PNG row layout");
  std::vector<unsigned char> data(row_bytes * std::size_t(header.height));
  std::vector<png_bytep> rows(std::size_t(header.height));
  for (int y = 0; y < header.height; ++y) rows[std::size_t(y)] = data.data() + row_bytes * std::size_t(y);
  if (!read_rows(f.get(), rows.data())) throw Error(where, std::string("cannot decode image: ") + f->error);

  if (!wide) return from_8bit(header.width, header.height, header.channels, data);
  Image img(header.width, header.height, header.channels);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    std::uint16_t v;
    std::memcpy(&v, &data[2 * i], 2);
    img.pixels[i] = float(v) * (1.0f / 65535.0f);
  }
  return img;
}

void write_png(const fs::path& file, const fs::path& target, int width, int height, int channels,
               const std::vector<unsigned char>& bytes) {
  const Location where{target.string()};
  if (channels < 1 || channels > 4)
    throw Error(where, "a PNG holds 1 to 4 channels, not " + std::to_string(channels) + "; write .exr instead");
  auto f = std::make_unique<PngFile>();
  f->writing = true;
  f->file = std::fopen(file.c_str(), "wb");
  if (f->file == nullptr) throw Error(where, std::string("cannot open for writing: ") + std::strerror(errno));
  f->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, f.get(), on_error, on_warning);
  if (f->png != nullptr) f->info = png_create_info_struct(f->png);
  if (f->png == nullptr || f->info == nullptr) throw Error(where, "cannot start the PNG encoder (out of memory)");
  const std::size_t row_bytes = std::size_t(width) * channels;
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y)
    rows[std::size_t(y)] = const_cast<png_bytep>(bytes.data()) + row_bytes * std::size_t(y);
  if (!write_all(f.get(), width, height, channels, rows.data()))
    throw Error(where, std::string("write failed: ") + f->error);
  const int closed = std::fclose(f->file);
  f->file = nullptr;
  if (closed != 0) throw Error(where, std::string("write failed: ") + std::strerror(errno));
}

}  // namespace plumage::codec
