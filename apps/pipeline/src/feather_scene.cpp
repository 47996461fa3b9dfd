#include "plumage/pipeline/feather_scene.h"

#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"

namespace plumage {

std::size_t LoadedScene::placed_barbs() const {
  std::size_t n = 0;
  for (const ScenePlacement& p : scene.placements) n += feathers[p.feather].count(CurveKind::Barb);
  return n;
}

LoadedScene load_scene(const std::filesystem::path& path) {
  LoadedScene out;
  out.scene = read_fscene(path);
  const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
  for (const SceneFeather& f : out.scene.feathers) {
    const Location where{path.string(), f.line, 1};
    try {
      if (f.source == SceneFeatherSource::Fcurves) {
        const std::filesystem::path file = std::filesystem::path(f.path).is_absolute() ? std::filesystem::path(f.path) : folder / f.path;
        out.feathers.push_back(read_fcurves(file));
        out.folders.push_back(file.parent_path().empty() ? "." : file.parent_path());
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

BuiltWorld::BuiltWorld(const LoadedScene& loaded, const SceneOptions& options, const ViewSpec& view) {
  SceneOptions per_feather = options;
  per_feather.backdrop.enabled = false;
  std::vector<WorldFeather> feathers;
  for (std::size_t i = 0; i < loaded.feathers.size(); ++i) {
    const Feather& f = loaded.feathers[i];
    scenes_.push_back(std::make_unique<Scene>(f, per_feather));
    ViewSpec v = view;
    v.base_dir = loaded.folders[i];
    materials_.push_back(std::make_unique<FibreMaterial>(view_material(f, v, options.mode)));
    feathers.push_back({scenes_.back().get(), materials_.back().get()});
    for (const Curve& c : f.curves) feather_bytes_ += c.points.size() * sizeof(ControlPoint);
  }
  std::vector<WorldPlacement> placements;
  placements.reserve(loaded.scene.placements.size());
  for (const ScenePlacement& p : loaded.scene.placements)
    placements.push_back({std::uint32_t(p.feather), p.to_world});
  world_ = std::make_unique<World>(std::move(feathers), std::move(placements), options.backdrop);
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
