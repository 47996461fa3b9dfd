#pragma once
// The scene the rendering benchmarks share: the rock-dove preset (seed 1) under
// the 25-LED dome, seen from straight above the vane at (10, 60) mm, 64x64 pixels
// at 4 samples on one thread, so a figure is per core.
#include <filesystem>

#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/feather_render.h"

namespace plumage::bench {

inline const Feather& rock_dove() {
  static const Feather f = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  return f;
}

inline const DomeRig& dome25() {
  static const DomeRig r = read_dome_rig(std::filesystem::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  return r;
}

// A top view `height_mm` over the vane at (10, 60); at 15 mm it is about 8 mm across.
inline ViewSpec top_view(float height_mm) {
  ViewSpec v;
  v.width = v.height = 64;
  v.spp = 4;
  v.threads = 1;
  v.camera.position = glm::vec3(10.0f, 60.0f, height_mm);
  v.camera.look_at = glm::vec3(10.0f, 60.0f, 0.0f);
  return v;
}

}  // namespace plumage::bench
