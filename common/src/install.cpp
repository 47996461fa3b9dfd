#include "plumage/common/install.h"

#include <climits>
#include <cstdlib>
#include <system_error>
#include <unistd.h>

#include "plumage_build_info.h"  // generated at build time: PLUMAGE_VERSION, PLUMAGE_COMMIT

namespace plumage {
namespace fs = std::filesystem;

fs::path executable_folder() {
  char exe[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return {};
  return fs::path(std::string(exe, std::size_t(n))).parent_path();
}

fs::path data_dir() {
  if (const char* env = std::getenv("PLUMAGE_DATA_DIR"); env && *env) return fs::path(env);
  if (const fs::path bin = executable_folder(); bin.filename() == "bin") {
    const fs::path installed = bin.parent_path() / kInstallDataFolder;
    std::error_code ec;
    if (fs::is_directory(installed / "rigs", ec)) return installed;
  }
  return fs::path(PLUMAGE_SOURCE_DATA_DIR);
}

std::string version_text() { return std::string("plumage ") + PLUMAGE_VERSION + " (commit " + PLUMAGE_COMMIT + ")"; }

}  // namespace plumage
