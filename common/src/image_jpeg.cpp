// JPEG through libjpeg (libjpeg-turbo on Debian; image_codecs.h). Most photos
// are JPEG, and decoding them here spares a process OpenImageIO's module and
// its ~260 libraries (about 0.25 s to load, docs/perf/analysis.md); overlays
// and study pictures are written as JPEG here for the same reason. CMYK and
// YCCK files, whose colour needs converting, still go to the module. libjpeg
// reports errors through an error_exit that must not return, so it jumps back
// to the frame that called into libjpeg; that frame owns only libjpeg's state,
// kept on the heap, and what throws runs after libjpeg returned.
#include <cstdio>
// jpeglib.h needs FILE and size_t declared before it.
#include <jpeglib.h>
#include <jerror.h>

#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <memory>

#include "image_codecs.h"
#include "plumage/common/error.h"

namespace plumage::codec {
namespace fs = std::filesystem;

namespace {
// libjpeg's error handling for one file: its error text and the jump back.
struct JpegErrors {
  jpeg_error_mgr mgr{};
  char error[JMSG_LENGTH_MAX] = {};
  std::jmp_buf jump;
};

[[noreturn]] void on_error(j_common_ptr cinfo) {
  auto* e = static_cast<JpegErrors*>(cinfo->client_data);
  (*cinfo->err->format_message)(cinfo, e->error);
  std::longjmp(e->jump, 1);
}
// Messages are not printed: stderr stays ours.
void on_message(j_common_ptr) {}
// A warning of corrupt data (a scan that ends early, a marker inside the data,
// a file that ends early) stops the decoding as an error: libjpeg would fill the
// rest of the picture with grey and go on, and a 22 KB file whose header claims
// 11000 x 11000 pixels cost 27 s and 1.8 GB before anything judged it. Extraneous
// bytes before a marker, which some cameras write, and trace messages (level > 0)
// are let pass.
void on_emit(j_common_ptr cinfo, int level) {
  if (level < 0 && cinfo->err->msg_code != JWRN_EXTRANEOUS_DATA) on_error(cinfo);
}

// Points `cinfo` (a jpeg_compress_struct or jpeg_decompress_struct) at `e`.
template <class Info>
void attach(Info& cinfo, JpegErrors& e) {
  cinfo.err = jpeg_std_error(&e.mgr);
  e.mgr.error_exit = on_error;
  e.mgr.output_message = on_message;
  e.mgr.emit_message = on_emit;
  cinfo.client_data = &e;
}

// libjpeg's state for one file: a jpeg_decompress_struct to read, a
// jpeg_compress_struct to write (jpeg_destroy frees either).
template <class Info>
struct JpegState : JpegErrors {
  Info cinfo{};
  bool created = false;
  std::FILE* file = nullptr;
  ~JpegState() {
    if (created) jpeg_destroy(reinterpret_cast<j_common_ptr>(&cinfo));
    if (file != nullptr) std::fclose(file);
  }
};
using JpegFile = JpegState<jpeg_decompress_struct>;
using JpegOut = JpegState<jpeg_compress_struct>;

enum class Opened { ok, needs_module, failed };

// Reads the header and asks for 8-bit grey or RGB samples.
Opened read_header(JpegFile* f) {
  if (setjmp(f->jump) != 0) return Opened::failed;
  attach(f->cinfo, *f);
  jpeg_create_decompress(&f->cinfo);
  f->created = true;
  jpeg_stdio_src(&f->cinfo, f->file);
  jpeg_read_header(&f->cinfo, TRUE);
  if (f->cinfo.jpeg_color_space == JCS_CMYK || f->cinfo.jpeg_color_space == JCS_YCCK) return Opened::needs_module;
  f->cinfo.out_color_space = f->cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  return Opened::ok;
}

// False on a libjpeg error, or (with `error` set) when the output is not the
// layout the buffer was sized for.
bool read_rows(JpegFile* f, unsigned char* data, std::size_t row_bytes, int width, int channels, int height) {
  if (setjmp(f->jump) != 0) return false;
  jpeg_start_decompress(&f->cinfo);
  if (int(f->cinfo.output_width) != width || int(f->cinfo.output_components) != channels ||
      int(f->cinfo.output_height) != height) {
    std::snprintf(f->error, sizeof f->error, "unexpected JPEG output layout");
    return false;
  }
  while (f->cinfo.output_scanline < f->cinfo.output_height) {
    JSAMPROW row = data + row_bytes * f->cinfo.output_scanline;
    jpeg_read_scanlines(&f->cinfo, &row, 1);
  }
  jpeg_finish_decompress(&f->cinfo);
  return true;
}

// Colour (or grey) rows of `bytes`, `channels` samples a pixel, the alpha of 2 or
// 4 channels left out; false on a libjpeg error.
bool write_rows(JpegOut* f, int width, int height, int channels, const unsigned char* bytes, int quality) {
  if (setjmp(f->jump) != 0) return false;
  attach(f->cinfo, *f);
  jpeg_create_compress(&f->cinfo);
  f->created = true;
  jpeg_stdio_dest(&f->cinfo, f->file);
  const int colour = channels >= 3 ? 3 : 1;
  f->cinfo.image_width = JDIMENSION(width);
  f->cinfo.image_height = JDIMENSION(height);
  f->cinfo.input_components = colour;
  f->cinfo.in_color_space = colour == 3 ? JCS_RGB : JCS_GRAYSCALE;
  jpeg_set_defaults(&f->cinfo);
  jpeg_set_quality(&f->cinfo, quality, TRUE);
  jpeg_start_compress(&f->cinfo, TRUE);
  std::vector<unsigned char> row(std::size_t(width) * std::size_t(colour));
  while (f->cinfo.next_scanline < f->cinfo.image_height) {
    const unsigned char* in = bytes + std::size_t(f->cinfo.next_scanline) * std::size_t(width) * std::size_t(channels);
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < colour; ++c)
        row[std::size_t(x * colour + c)] = in[std::size_t(x) * std::size_t(channels) + std::size_t(c)];
    JSAMPROW r = row.data();
    jpeg_write_scanlines(&f->cinfo, &r, 1);
  }
  jpeg_finish_compress(&f->cinfo);
  return true;
}
}  // namespace

Image read_jpeg(const fs::path& path, const HeaderCheck& check, Header& header) {
  const Location where{path.string()};
  auto f = std::make_unique<JpegFile>();
  f->file = std::fopen(path.c_str(), "rb");
  if (f->file == nullptr) throw Error(where, std::string("cannot open: ") + std::strerror(errno));
  const Opened opened = read_header(f.get());
  if (opened == Opened::failed) throw Error(where, std::string("cannot read as an image: ") + f->error);
  if (opened == Opened::needs_module) {
    f.reset();
    return read_with_module(path, check, header);
  }
  header.width = int(f->cinfo.image_width);
  header.height = int(f->cinfo.image_height);
  header.channels = f->cinfo.out_color_space == JCS_GRAYSCALE ? 1 : 3;
  header.alpha = -1;
  header.is_float = false;
  header.bits = 8;
  check(header);

  const std::size_t row_bytes = std::size_t(header.width) * std::size_t(header.channels);
  std::vector<unsigned char> data(row_bytes * std::size_t(header.height));
  if (!read_rows(f.get(), data.data(), row_bytes, header.width, header.channels, header.height))
    throw Error(where, std::string("cannot decode image: ") + f->error);
  return from_8bit(header.width, header.height, header.channels, data);
}

void write_jpeg(const fs::path& file, const fs::path& target, int width, int height, int channels,
                const std::vector<unsigned char>& bytes, int quality) {
  const Location where{target.string()};
  if (channels < 1 || channels > 4)
    throw Error(where, "a JPEG holds 1 to 4 channels (alpha is left out), not " + std::to_string(channels) +
                           "; write .exr instead");
  if (width > JPEG_MAX_DIMENSION || height > JPEG_MAX_DIMENSION)
    throw Error(where, "a JPEG is at most " + std::to_string(JPEG_MAX_DIMENSION) + " px a side; write .png instead");
  auto f = std::make_unique<JpegOut>();
  f->file = std::fopen(file.c_str(), "wb");
  if (f->file == nullptr) throw Error(where, std::string("cannot open for writing: ") + std::strerror(errno));
  if (!write_rows(f.get(), width, height, channels, bytes.data(), quality > 0 ? quality : kDefaultJpegQuality))
    throw Error(where, std::string("write failed: ") + f->error);
  const int closed = std::fclose(f->file);
  f->file = nullptr;
  if (closed != 0) throw Error(where, std::string("write failed: ") + std::strerror(errno));
}

}  // namespace plumage::codec
