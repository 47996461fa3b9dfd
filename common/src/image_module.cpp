// Loads the OpenImageIO module (image_module_abi.h) on first use: from beside
// the executable or shared library this code is linked into, else from the
// build tree it was built in (the fuzz targets live in a subfolder of theirs).
#include <dlfcn.h>
#include <link.h>

#include <climits>
#include <mutex>
#include <string>

#include "image_codecs.h"
#include "image_module_abi.h"
#include "plumage/common/error.h"
#include "plumage/common/install.h"
#include "plumage/common/stderr_capture.h"

#ifndef PLUMAGE_IMAGE_MODULE_BUILD_DIR
#define PLUMAGE_IMAGE_MODULE_BUILD_DIR ""
#endif

namespace plumage::codec {
namespace fs = std::filesystem;

namespace {
// The folder of the object (executable or library) that holds this function.
fs::path own_folder() {
  Dl_info info{};
  link_map* map = nullptr;
  if (dladdr1(reinterpret_cast<void*>(&own_folder), &info, reinterpret_cast<void**>(&map), RTLD_DL_LINKMAP) != 0 &&
      map != nullptr && map->l_name != nullptr && map->l_name[0] == '/')
    return fs::path(map->l_name).parent_path();
  return executable_folder();  // the main program has no name in the link map
}

struct Loaded {
  const PlumageImageModule* module = nullptr;
  std::string error;  // why it could not be loaded
};

Loaded load() {
  std::vector<fs::path> places;
  if (const fs::path own = own_folder(); !own.empty()) {
    places.push_back(own / kImageModuleFile);  // the build folder's executables
    places.push_back(own.parent_path() / kInstallModuleFolder / kImageModuleFile);  // PREFIX/bin -> PREFIX/lib/plumage
  }
  if (const fs::path built = PLUMAGE_IMAGE_MODULE_BUILD_DIR; !built.empty()) places.push_back(built / kImageModuleFile);
  std::string looked;
  for (const fs::path& p : places) {
    looked += (looked.empty() ? "" : " nor ") + p.string();
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) continue;
    void* handle = ::dlopen(p.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) return {nullptr, "cannot load " + p.string() + " (" + ::dlerror() + "); rebuild plumage"};
    using Entry = const PlumageImageModule* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(handle, kImageModuleEntry));
    const PlumageImageModule* module = entry != nullptr ? entry() : nullptr;
    if (module == nullptr || module->abi != kImageModuleAbi)
      return {nullptr, p.string() + " is not this version's image module; rebuild plumage"};
    return {module, {}};  // kept loaded for the life of the process
  }
  return {nullptr, std::string("formats other than PNG and OpenEXR need OpenImageIO's module ") + kImageModuleFile +
                       ", which is not there (looked for " + looked + "); build it (cmake --build) or convert the image to PNG or EXR"};
}

const PlumageImageModule& module_for(const fs::path& path) {
  static std::once_flag once;
  static Loaded loaded;
  std::call_once(once, [] { loaded = load(); });
  if (loaded.module == nullptr) throw Error(Location{path.string()}, loaded.error);
  return *loaded.module;
}
}  // namespace

Image read_with_module(const fs::path& path, const HeaderCheck& check, Header& header) {
  const Location where{path.string()};
  const PlumageImageModule& m = module_for(path);
  // The decoders' own stderr lines (libjpeg, libtiff) go into our error message, or nowhere.
  StderrCapture decoder_messages;
  const auto why = [&](const char* error) { return error[0] != '\0' ? std::string(error) : decoder_messages.text(); };
  char error[1024] = {};
  PlumageImageHeader h{};
  void* handle = m.open(path.c_str(), &h, error, sizeof error);
  if (handle == nullptr) {
    const std::string because = why(error);
    throw Error(where, "cannot read as an image" + (because.empty() ? std::string() : ": " + because));
  }
  struct Closer {
    const PlumageImageModule& m;
    void* handle;
    ~Closer() { m.close(handle); }
  } closer{m, handle};
  header = {h.width, h.height, h.channels, h.alpha, h.is_float != 0, h.bits};
  if (header.width <= 0 || header.height <= 0 || header.channels <= 0) throw Error(where, "image has no pixels");
  check(header);
  Image img(header.width, header.height, header.channels);
  if (m.read(handle, img.pixels.data(), error, sizeof error) == 0)
    throw Error(where, "cannot decode image: " + why(error));
  return img;
}

void write_with_module(const fs::path& file, const fs::path& target, const std::string& format, int width, int height,
                       int channels, bool is_float, const void* samples, int quality) {
  const PlumageImageModule& m = module_for(target);
  char error[1024] = {};
  if (m.write(file.c_str(), format.c_str(), width, height, channels, is_float ? 1 : 0, samples, quality, error,
              sizeof error) == 0)
    throw Error(Location{target.string()}, std::string("write failed: ") + error);
}

}  // namespace plumage::codec
