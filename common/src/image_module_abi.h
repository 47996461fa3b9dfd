#pragma once
// The C interface between read_image/write_image (image_module.cpp) and the
// OpenImageIO module (common/module/image_oiio.cpp, built as
// plumage_image_oiio.so beside the executables). Plain C types only: the module
// is loaded with dlopen and found by the one symbol kImageModuleEntry names.
#include <cstddef>

extern "C" {

struct PlumageImageHeader {
  int width, height, channels;
  int alpha;     // alpha channel index or -1
  int is_float;  // float, half or double samples
  int bits;      // bits per sample as stored
};

struct PlumageImageModule {
  int abi;  // kImageModuleAbi
  // Opens `path` and reads its header: returns a handle, or null with a message in `error`.
  void* (*open)(const char* path, PlumageImageHeader* header, char* error, std::size_t error_size);
  // Decodes every channel of the opened image into `pixels` as float; 0 on failure.
  int (*read)(void* handle, float* pixels, char* error, std::size_t error_size);
  void (*close)(void* handle);
  // Writes `file` in `format` (an extension without its dot): float samples when
  // `is_float`, else 8-bit; `quality` 1-100 for JPEG, 0 for the default. 0 on failure.
  int (*write)(const char* file, const char* format, int width, int height, int channels, int is_float,
               const void* samples, int quality, char* error, std::size_t error_size);
};

}  // extern "C"

namespace plumage::codec {
inline constexpr int kImageModuleAbi = 2;
inline constexpr const char* kImageModuleEntry = "plumage_image_module_v1";
inline constexpr const char* kImageModuleFile = "plumage_image_oiio.so";
}  // namespace plumage::codec
