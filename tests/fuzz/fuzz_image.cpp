// Fuzzes the image reader (common/image.h): any bytes, as a PNG, JPEG, EXR or
// TIFF file, are read or refused with plumage::Error; what is read has the size
// its header promised, within the megapixel limit, and no read crashes or hangs.
// The bytes go to a file because read_image reads files (OpenImageIO), named by
// the first byte's choice of extension so each decoder gets its share.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "plumage/common/image.h"
#include "fuzz_verdict.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kExt[] = {".png", ".jpg", ".exr", ".tif", ".hdr"};
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("plumage_fuzz_image_" + std::to_string(::getpid()) + kExt[data[0] % 5]);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
  }
  plumage::fuzz::expect_parse_or_error([&] {
    (void)plumage::damage_of(file);
    // A small limit keeps each run fast; the check itself is what is fuzzed.
    const plumage::Image img = plumage::read_image(file, true, 4.0);
    plumage::fuzz::check(img.width > 0 && img.height > 0 && img.channels > 0, "an image without pixels was returned");
    plumage::fuzz::check(double(img.width) * img.height <= 4.0e6, "the megapixel limit was not kept");
    plumage::fuzz::check(img.pixels.size() == std::size_t(img.width) * img.height * img.channels,
                         "pixel count does not match the size");
  });
  std::error_code ec;
  std::filesystem::remove(file, ec);
  return 0;
}
