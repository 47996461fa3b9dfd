#pragma once
// A scene of many feathers (.fscene, docs/scene-format.md) from file to renderable
// world: its distinct feathers read or generated once each, then one Scene and one
// material per distinct feather and a World that places them (renderer/world.h).
// `plumage render`, `info` and `export` share it.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "plumage/common/feather.h"
#include "plumage/common/scene_format.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/panel_layout.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/world.h"

namespace plumage {

struct LoadedScene {
  FeatherScene scene;
  std::vector<Feather> feathers;                // per SceneFeather, in the file's order
  std::vector<std::filesystem::path> folders;   // per feather: where its albedo texture paths start
  // Barbs over every placement (a feather placed twice counts twice).
  std::size_t placed_barbs() const;
};

// Reads `path` and every feather it defines: .fcurves files relative to the scene's
// folder, presets generated with their seeds. Throws plumage::Error naming the
// scene's FILE:LINE of the feather that cannot be read or built.
LoadedScene load_scene(const std::filesystem::path& path);

// How the placements of a scene are shaded: all in SceneOptions::mode, or each by
// its pixel footprint (`--shading auto`, shading_level.h): substructure mode where a
// pixel over it is smaller than its feather's barbule period, farfield elsewhere.
enum class SceneShading { Uniform, ByFootprint };

// One Scene and one material per distinct feather and shading mode used, and the
// world placing them.
class BuiltWorld {
 public:
  // `options.backdrop` becomes the world's card (the feathers' scenes get none);
  // `view` gives the materials as view_material does for one feather (its base_dir
  // replaced by each feather's folder) and, for ByFootprint, the camera whose
  // footprint decides. A feather whose placements fall on both sides of the switch
  // is built twice (substructure and farfield), sharing its ribbon-layer map.
  BuiltWorld(const LoadedScene& loaded, const SceneOptions& options, const ViewSpec& view,
             SceneShading shading = SceneShading::Uniform);
  const World& world() const { return *world_; }
  // The mode each placement is shaded in, in the scene's order.
  const std::vector<ShadingMode>& placement_modes() const { return placement_modes_; }
  // Bytes of the distinct feathers' control points (each feather once, whatever
  // its placements) and of the world's placement records.
  std::size_t feather_bytes() const { return feather_bytes_; }
  std::size_t placement_bytes() const { return world_->placement_bytes(); }

 private:
  std::vector<std::unique_ptr<Scene>> scenes_;
  std::vector<std::unique_ptr<FibreMaterial>> materials_;
  std::unique_ptr<World> world_;
  std::vector<ShadingMode> placement_modes_;
  std::size_t feather_bytes_ = 0;
};

// The scene in hair and then substructure shading under the same view: one labelled
// panel each (`plumage compare scene.fscene`).
std::vector<Panel> render_scene_both_modes(const LoadedScene& loaded, SceneOptions options, const DomeRig& rig,
                                           const ViewSpec& view);

}  // namespace plumage
