#pragma once
// The capture rig of the paper (DESIGN §7): white LEDs on a hemisphere over the
// feather, read from a JSON file such as data/rigs/dome25.json (docs/rendering.md
// describes the file and how the 25 positions were laid out).
#include <filesystem>
#include <string>
#include <limits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/renderer/sphere_light.h"

namespace plumage {

struct DomeRig {
  std::string name;
  float led_radius = 2.5f;        // mm
  glm::vec3 intensity{1.0f};      // radiant intensity of one LED, W/sr (RGB)
  std::vector<glm::vec3> leds;    // positions relative to the rig centre (mm); LED k is leds[k-1]
};

// Throws plumage::Error with FILE:LINE:COL for malformed JSON and FILE plus the
// field for missing or absurd values.
DomeRig read_dome_rig(const std::filesystem::path& path);
// The paper's 25-LED dome, rigs/dome25.json in plumage's data folder (install.h).
std::filesystem::path default_rig_path();
DomeRig parse_dome_rig(const std::string& text, const std::string& filename);

// "all", "none", or a comma list of 1-based LED numbers and ranges ("1,5,12", "1-8,13").
// The grammar alone, without a rig: the ranges as written, 1-based and inclusive
// ({1, count} for "all", none for "none"); throws plumage::Error naming --lights for
// anything else. The command line checks it while it parses (a usage error).
std::vector<std::pair<int, int>> light_ranges(const std::string& spec, int count = std::numeric_limits<int>::max());
// Returns sorted unique 0-based indices; throws plumage::Error for a number outside 1..count.
std::vector<int> parse_light_selection(const std::string& spec, int count);

// The selected LEDs as sphere lights, the rig centred at `centre`.
std::vector<SphereLight> dome_lights(const DomeRig& rig, const std::vector<int>& selection,
                                     const glm::vec3& centre);

}  // namespace plumage
