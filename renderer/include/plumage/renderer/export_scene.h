#pragma once
// What `plumage render` would render, as the plain numbers the exporters write
// (common/exporters.h): the camera of the view, the rig's selected LEDs standing
// where the renderer puts them, the backdrop card, the hair material with the
// absorption the renderer gives the feather, and the depth. Each value comes from
// the renderer's own code (Camera, view_lights, view_material, Scene's bounds and
// backdrop), so an export and a render of the same view agree by construction.
#include "plumage/common/exporters.h"
#include "plumage/common/feather.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/world.h"

namespace plumage {

// `options` gives the shading mode and backdrop (its cull is ignored); substructure
// and explicit modes are exported as hair (ExportScene::shading says which mode the
// scene stands for). Throws plumage::Error for what render_view would reject (bad
// LED selection, camera, material), and for an environment map, which the exporters
// cannot carry (a constant environment they can).
ExportScene export_scene(const Feather& feather, const DomeRig& rig, const ViewSpec& view,
                         const SceneOptions& options);

// The same for a world of placed feathers (world.h; `plumage export scene.fscene`):
// the camera frames the world, the card is the world's, and `materials` receives
// each distinct feather's material as above, in the world's order (ExportScene::
// material is feather 0's). `mode` is the mode the scene stands for.
ExportScene export_scene(const World& world, const DomeRig& rig, const ViewSpec& view, ShadingMode mode,
                         std::vector<ExportMaterial>& materials);

}  // namespace plumage
