// JPEG through libjpeg (libjpeg-turbo on Debian; image_codecs.h). Most photos
// are JPEG, and decoding them here spares a process OpenImageIO's module and
// its ~260 libraries (about 0.25 s to load, docs/perf/analysis.md). CMYK and
// YCCK files, whose colour needs converting, still go to the module. libjpeg
// reports errors through an error_exit that must not return, so it jumps back
// to the frame that called into libjpeg; that frame owns only libjpeg's state,
// kept on the heap, and what throws runs after libjpeg returned.
#include <cstdio>
// jpeglib.h needs FILE and size_t declared before it.
#include <jpeglib.h>

#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <memory>

#include "image_codecs.h"
#include "plumage/common/error.h"

namespace plumage::codec {
namespace fs = std::filesystem;

namespace {
// libjpeg's state for one file, with its error text and the jump back from it.
struct JpegFile {
  jpeg_decompress_struct cinfo{};
  jpeg_error_mgr err{};
  bool created = false;
  std::FILE* file = nullptr;
  char error[JMSG_LENGTH_MAX] = {};
  std::jmp_buf jump;
  ~JpegFile() {
    if (created) jpeg_destroy_decompress(&cinfo);
    if (file != nullptr) std::fclose(file);
  }
};

[[noreturn]] void on_error(j_common_ptr cinfo) {
  auto* f = static_cast<JpegFile*>(cinfo->client_data);
  (*cinfo->err->format_message)(cinfo, f->error);
  std::longjmp(f->jump, 1);
}
// Warnings (extraneous bytes before a marker, a corrupt entropy segment) are
// dropped: the pixels libjpeg hands back are the answer, and stderr stays ours.
void on_message(j_common_ptr) {}

enum class Opened { ok, needs_module, failed };

// Reads the header and asks for 8-bit grey or RGB samples.
Opened read_header(JpegFile* f) {
  if (setjmp(f->jump) != 0) return Opened::failed;
  f->cinfo.err = jpeg_std_error(&f->err);
  f->err.error_exit = on_error;
  f->err.output_message = on_message;
  f->cinfo.client_data = f;
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

}  // namespace plumage::codec
