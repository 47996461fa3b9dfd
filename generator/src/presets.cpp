#include "plumage/generator/presets.h"

#include <algorithm>
#include <cstdlib>

#include "plumage/common/error.h"
#include "plumage/common/install.h"

namespace plumage {
namespace fs = std::filesystem;

fs::path presets_dir() { return data_dir() / "presets"; }

std::vector<std::string> list_presets() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(presets_dir(), ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

FeatherParams load_preset(const std::string& name) {
  const auto names = list_presets();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown preset '" + name + "'; known presets: " + (known.empty() ? "(none found in " + presets_dir().string() + ")" : known) +
                " (see `plumage generate --list-presets`)");
  }
  return read_params(presets_dir() / (name + ".json"));
}

}  // namespace plumage
