#include "plumage/pipeline/feather_scene.h"

#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/layout/layout.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/shading_level.h"

namespace plumage {

std::size_t LoadedScene::placed_barbs() const {
  std::size_t n = 0;
  for (const ScenePlacement& p : scene.placements) n += feathers[p.feather].count(CurveKind::Barb);
  return n;
}

LoadedScene load_scene(const std::filesystem::path& path) {
  LoadedScene out;
  out.scene = read_fscene(path);
  const auto folder_of = [](const std::filesystem::path& file) {
    return file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
  };
  const std::filesystem::path folder = folder_of(path);
  // A feather's file: relative paths start at the scene file's folder.
  const auto resolved = [&](const std::string& p) {
    return std::filesystem::path(p).is_absolute() ? std::filesystem::path(p) : folder / p;
  };
  for (const SceneFeather& f : out.scene.feathers) {
    const Location where{path.string(), f.line, 1};
    try {
      if (f.source == SceneFeatherSource::Fcurves) {
        const std::filesystem::path file = resolved(f.path);
        out.feathers.push_back(read_fcurves(file));
        out.folders.push_back(folder_of(file));
      } else if (f.source == SceneFeatherSource::Layout) {
        // The curves `plumage generate --layout FILE --feather ID --seed N` builds,
        // coloured by the mean of the analysed albedo under the photo's mask (as
        // `plumage wing --layout` colours its keys): the texture generate would
        // write beside a curve file is not written by a render.
        const std::filesystem::path file = resolved(f.path);
        const std::filesystem::path dir = folder_of(file);
        const Layout layout = read_layout(file);
        const FeatherLayout& chosen = pick_feather(layout, int(f.layout_feather), file.string());
        Feather feather = layout_to_feather(chosen, f.seed, dir, dir, file.string());
        if (!feather.albedo.texture.empty()) {
          const glm::dvec3 mean = albedo_mean(read_image(dir / chosen.albedo.file)).value_or(glm::dvec3(0.5));
          feather.albedo.color = glm::vec3(mean * double(feather.albedo.scale));
          feather.albedo.texture.clear();
          feather.albedo.scale = 1;
        }
        out.feathers.push_back(std::move(feather));
        out.folders.push_back(dir);
      } else {
        out.feathers.push_back(build_feather(load_preset(f.preset), f.seed, "preset:" + f.preset));
        out.folders.push_back(folder);
      }
    } catch (const Error& e) {
      throw Error(where, "feather '" + f.name + "': " + e.what());
    }
  }
  return out;
}

BuiltWorld::BuiltWorld(const LoadedScene& loaded, const SceneOptions& options, const ViewSpec& view,
                       SceneShading shading) {
  SceneOptions per_feather = options;
  per_feather.backdrop.enabled = false;
  if (shading == SceneShading::ByFootprint) per_feather.mode = ShadingMode::Substructure;
  const std::size_t n = loaded.feathers.size();
  // Each feather in the uniform mode (ByFootprint: substructure, which also gives
  // the bounds the camera frames).
  std::vector<WorldFeather> feathers;
  for (std::size_t i = 0; i < n; ++i) {
    const Feather& f = loaded.feathers[i];
    scenes_.push_back(std::make_unique<Scene>(f, per_feather));
    ViewSpec v = view;
    v.base_dir = loaded.folders[i];
    materials_.push_back(std::make_unique<FibreMaterial>(view_material(f, v, per_feather.mode)));
    feathers.push_back({scenes_.back().get(), materials_.back().get()});
    for (const Curve& c : f.curves) feather_bytes_ += c.points.size() * sizeof(ControlPoint);
  }
  std::vector<WorldPlacement> placements;
  placements.reserve(loaded.scene.placements.size());
  for (const ScenePlacement& p : loaded.scene.placements)
    placements.push_back({std::uint32_t(p.feather), p.to_world});
  world_ = std::make_unique<World>(feathers, placements, options.backdrop);
  placement_modes_.assign(placements.size(), per_feather.mode);
  if (shading == SceneShading::Uniform) return;

  // The camera render_view frames the world with; each placement's level from it.
  const Camera camera(view.camera, view.width, view.height, world_->bounds());
  std::vector<float> period(n);  // each feather's once, however often it is placed
  for (std::size_t i = 0; i < n; ++i) period[i] = barbule_period(loaded.feathers[i]);
  std::vector<bool> near(n, false), far(n, false);
  for (std::uint32_t i = 0; i < placements.size(); ++i) {
    const std::uint32_t f = placements[i].feather;
    placement_modes_[i] = shading_for_footprint(camera.pixel_footprint(world_->placement_bounds(i)),
                                                world_->placement_scale(i) * period[f]);
    (placement_modes_[i] == ShadingMode::Farfield ? far : near)[f] = true;
  }
  // The world over the scenes the placements use: each feather's substructure
  // scene where a near placement shows it, its farfield scene (built now) where a
  // far one does.
  world_.reset();
  SceneOptions far_options = per_feather;
  far_options.mode = ShadingMode::Farfield;
  std::vector<WorldFeather> used;
  std::vector<std::uint32_t> near_index(n, 0), far_index(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (near[i]) {
      near_index[i] = std::uint32_t(used.size());
      used.push_back(feathers[i]);
    }
    if (far[i]) {
      const Feather& f = loaded.feathers[i];
      scenes_.push_back(std::make_unique<Scene>(f, far_options, scenes_[i]->ribbon_layer_map()));
      ViewSpec v = view;
      v.base_dir = loaded.folders[i];
      materials_.push_back(std::make_unique<FibreMaterial>(view_material(f, v, ShadingMode::Farfield)));
      far_index[i] = std::uint32_t(used.size());
      used.push_back({scenes_.back().get(), materials_.back().get()});
    }
  }
  for (std::uint32_t i = 0; i < placements.size(); ++i) {
    const std::uint32_t f = placements[i].feather;
    placements[i].feather = placement_modes_[i] == ShadingMode::Farfield ? far_index[f] : near_index[f];
  }
  world_ = std::make_unique<World>(std::move(used), std::move(placements), options.backdrop);
  // Substructure scenes no placement shows are not kept.
  for (std::size_t i = 0; i < n; ++i)
    if (!near[i]) scenes_[i].reset();
}

std::vector<Panel> render_scene_both_modes(const LoadedScene& loaded, SceneOptions options, const DomeRig& rig,
                                           const ViewSpec& view) {
  std::vector<Panel> panels;
  for (ShadingMode mode : {ShadingMode::Hair, ShadingMode::Substructure}) {
    options.mode = mode;
    const BuiltWorld built(loaded, options, view);
    panels.push_back({render_view(built.world(), rig, view), to_string(mode)});
  }
  return panels;
}

}  // namespace plumage
