#pragma once
// Where a plumage binary finds its data (presets, light rigs) and its image
// module, whether it runs from the build folder or was installed
// (`cmake --install`, the .deb): docs/install.md. The installed layout is
//   PREFIX/bin/plumage
//   PREFIX/lib/plumage/plumage_image_oiio.so
//   PREFIX/share/plumage/{presets,rigs}/
// and every path is found from the binary's own place, so an installed plumage
// never reads the source tree it was built from.
#include <filesystem>
#include <string>

namespace plumage {

// The installed layout's folders, relative to PREFIX (CMakeLists.txt installs to them).
inline constexpr const char* kInstallDataFolder = "share/plumage";
inline constexpr const char* kInstallModuleFolder = "lib/plumage";

// The folder of the running executable (/proc/self/exe); empty if it cannot be read.
std::filesystem::path executable_folder();

// The data folder: $PLUMAGE_DATA_DIR when set; else PREFIX/share/plumage when the
// executable lies in PREFIX/bin and that folder holds rigs/; else the data/ folder
// of the source tree this binary was built from.
std::filesystem::path data_dir();

// "plumage 0.1.0 (commit 1a2b3c4d5e6f)": the project version and the git commit
// the build was made from ("unknown" outside a git checkout; "+" when it had
// uncommitted changes).
std::string version_text();

}  // namespace plumage
