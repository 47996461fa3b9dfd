#pragma once
// Species presets: FeatherParams JSON files in data/presets/ (docs/presets.md
// gives the sources of their numbers), in data_dir()/presets
// (plumage/common/install.h: $PLUMAGE_DATA_DIR, the installed share/plumage, or
// the source tree's data/).
#include <filesystem>
#include <string>
#include <vector>

#include "plumage/generator/feather_params.h"

namespace plumage {

std::filesystem::path presets_dir();
// Preset names (file names without .json), sorted.
std::vector<std::string> list_presets();
// Throws plumage::Error listing the known presets when `name` is not one of them.
FeatherParams load_preset(const std::string& name);

}  // namespace plumage
