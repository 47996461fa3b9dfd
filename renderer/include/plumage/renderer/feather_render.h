#pragma once
// One call from a feather to a developed image: the path every driver renders
// through (`plumage render`, `plumage compare`, their golden tests and the
// benchmarks): the dome rig's selected LEDs plus any environment and directional
// lights, the camera, the feather's albedo (or a given absorption), a backdrop card.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "plumage/common/image.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/fibre_material.h"
#include "plumage/renderer/hair_bcsdf.h"
#include "plumage/renderer/light_set.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/sampler.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/world.h"

namespace plumage {

struct ViewSpec {
  int width = 320, height = 480;
  int spp = 16;
  std::uint64_t seed = 0;
  SamplerKind sampler = SamplerKind::Sobol;
  int max_depth = 16;
  float exposure = 0;            // stops
  // > 0: expose like a camera metered on the card instead: the backdrop's centre,
  // lit by the selected LEDs, develops to this linear level (exposure is then ignored).
  float card_level = 0;
  std::string lights = "all";    // dome LEDs that are on (parse_light_selection)
  std::optional<EnvironmentLight> environment;  // added to the LEDs
  std::vector<DirectionalLight> directional;    // added to the LEDs
  CameraSpec camera;
  HairParams hair;               // sigma_a comes from the feather's albedo ...
  std::optional<glm::vec3> sigma_a;  // ... unless it is given here
  std::filesystem::path base_dir = ".";  // the curve file's folder (albedo texture paths)
  // Set: the albedo texture is a photo's, inverted through the card response over a
  // card of this albedo, the backdrop the feather lies on (FibreMaterial::set_card):
  // relative to the card (a light background, the paper divided out) unless
  // photo_texture_absolute (a dark background: the photo's own colour).
  std::optional<glm::vec3> photo_card;
  bool photo_texture_absolute = false;
  // Per channel, the factor on the photo texture's mean, applied as a shift of every
  // texel before the inversion (FibreMaterial::set_card's mean_gain):
  // photo-to-feather's colour calibration of a shading mode (colour_calibration.h).
  glm::vec3 photo_gain{1.0f};
  int threads = 0;
  bool progress = false;
  SampleAllocation allocation = RenderSettings{}.allocation;
  bool adaptive = false;         // RenderSettings: adaptive sampling, off by default
  float target_error = 0.02f;
  int min_spp = 16;
  LightPick light_pick = IntegratorSettings{}.light_pick;  // next-event estimation's choice of light
  int tile_index = 0, tile_count = 1;  // RenderSettings: one part of a split render
  // Filter the render by its own per-pixel variance (denoise.h); biased, so off by
  // default.
  bool denoise = false;
};

// The lights of `view`: the rig's selected LEDs, the rig standing on the
// feather's lowest point (as in the photographs), then the view's environment
// and directional lights. Throws plumage::Error for a bad LED selection.
LightSet view_lights(const Bounds3f& feather_bounds, const DomeRig& rig, const ViewSpec& view);

// What the feather's fibres are made of in `view`: its hair parameters with the
// absorption given there, or else from the feather's albedo (a texture resolved
// against view.base_dir). Throws plumage::Error for unusable hair parameters or an
// unreadable texture.
// `mode` picks the card response (card_response.h) when view.photo_card is set.
FibreMaterial view_material(const Feather& feather, const ViewSpec& view, ShadingMode mode = ShadingMode::Hair);

// Renders `scene` under `rig` as `view` says and returns the image scaled by
// 2^exposure. Throws plumage::Error for bad settings (see render(), Camera).
Image render_view(const Scene& scene, const DomeRig& rig, const ViewSpec& view);
// The same for a world of placed feathers (world.h), each with the material its
// WorldFeather gives (view.hair and view.sigma_a are the caller's to apply), the
// rig standing under the world's bounds and the camera framing them.
Image render_view(const World& world, const DomeRig& rig, const ViewSpec& view);

}  // namespace plumage
