#pragma once
// One call from a feather to a developed image, for the drivers that render the
// same feather several times with identical settings (`plumage compare`, its
// golden test and the substructure benchmark): the dome rig's selected LEDs, the
// auto-framed camera, the feather's albedo, a backdrop card.
#include <cstdint>
#include <filesystem>
#include <string>

#include "plumage/common/image.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/hair_bcsdf.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/scene.h"

namespace plumage {

struct ViewSpec {
  int width = 320, height = 480;
  int spp = 16;
  std::uint64_t seed = 0;
  int max_depth = 16;
  float exposure = 0;            // stops
  // > 0: expose like a camera metered on the card instead: the backdrop's centre,
  // lit by the selected LEDs, develops to this linear level (exposure is then ignored).
  float card_level = 0;
  std::string lights = "all";    // dome LEDs that are on (parse_light_selection)
  CameraSpec camera;
  HairParams hair;               // sigma_a comes from the feather's albedo
  std::filesystem::path base_dir = ".";  // the curve file's folder (albedo texture paths)
  int threads = 0;
  bool progress = false;
  bool adaptive = false;         // RenderSettings: adaptive sampling, off by default
  float target_error = 0.02f;
  int min_spp = 16;
  LightPick light_pick = IntegratorSettings{}.light_pick;  // next-event estimation's choice of light
};

// Renders `scene` under `rig` as `view` says and returns the image scaled by
// 2^exposure. Throws plumage::Error for bad settings (see render(), Camera).
Image render_view(const Scene& scene, const DomeRig& rig, const ViewSpec& view);

}  // namespace plumage
