// The shared chains (photo_comparison.h): layout -> feather, both shading modes,
// and the photo beside its renders with their fidelity.
#include "plumage/pipeline/photo_comparison.h"
#include "plumage/common/image.h"

#include <algorithm>
#include <array>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/generator/preview.h"

namespace plumage {

Feather generate_from_layout(const FeatherLayout& layout, std::uint64_t seed, const std::filesystem::path& layout_path,
                             const std::filesystem::path& fcurves_path, const std::filesystem::path& preview_path,
                             int preview_size, FileBatch& outputs, std::vector<std::string>* warnings) {
  const std::filesystem::path out_dir = fcurves_path.parent_path().empty() ? "." : fcurves_path.parent_path();
  // The renderable albedo (mask filled) goes next to the curve file: NAME.albedo.png.
  const std::filesystem::path texture = std::filesystem::path(fcurves_path).replace_extension(".albedo.png");
  const std::filesystem::path layout_dir = layout_path.parent_path().empty() ? "." : layout_path.parent_path();
  Feather feather = layout_to_feather_with_albedo(layout, seed, layout_dir, out_dir, texture, layout_path.string(),
                                                  warnings, &outputs);
  validate_feather(feather);
  write_fcurves(outputs, fcurves_path, feather);
  if (!preview_path.empty()) write_image(outputs, preview_path, render_preview(feather, PreviewOptions{preview_size, true}));
  return feather;
}

namespace {
// The feather's two scenes, hair and substructure, both built before either
// renders, so a bad substructure parameter fails before any time is spent; the
// second takes the first's ribbon-layer map instead of drawing it again.
struct ModeScenes {
  ModeScenes(const Feather& feather, SceneOptions options)
      : hair(feather, with_mode(options, ShadingMode::Hair)),
        substructure(feather, with_mode(options, ShadingMode::Substructure), hair.ribbon_layer_map()) {}
  static SceneOptions with_mode(SceneOptions o, ShadingMode mode) {
    o.mode = mode;
    return o;
  }
  std::array<const Scene*, 2> both() const { return {&hair, &substructure}; }
  const Scene hair, substructure;
};
}  // namespace

std::vector<Panel> render_both_modes(const Feather& feather, SceneOptions scene, const DomeRig& rig,
                                     const ViewSpec& view) {
  const ModeScenes scenes(feather, scene);
  std::vector<Panel> panels;
  for (const Scene* s : scenes.both()) panels.push_back({render_view(*s, rig, view), to_string(s->options().mode)});
  return panels;
}

std::vector<Panel> light_sequence_sheets(const Feather& feather, SceneOptions scene, const DomeRig& rig,
                                         const ViewSpec& view, int columns) {
  const ModeScenes scenes(feather, scene);
  const std::vector<int> leds = parse_light_selection(view.lights, int(rig.leds.size()));
  if (leds.empty()) throw Error("--light-sequence with --lights none: no LED to switch on");
  std::vector<Panel> sheets;
  for (const Scene* s : scenes.both()) {
    const std::string name = to_string(s->options().mode);
    std::vector<Panel> tiles;
    for (int led : leds) {
      ViewSpec one = view;
      one.lights = std::to_string(led + 1);
      tiles.push_back({render_view(*s, rig, one), "LED " + std::to_string(led + 1)});
    }
    sheets.push_back({contact_sheet(tiles, columns, name + ": one LED at a time"), name});
  }
  return sheets;
}

namespace {
// The grid calibration probes are traced on: they need the mean over the mask, not
// its detail, so a render grid longer than kProbeSide pixels is coarsened by a whole
// factor to at most that. Not below: on a coarse grid a feather's edge mixes with
// the card, and where the render's silhouette is not the photo's (a blue-jay white
// plume read with half its neighbour, IoU 0.55) a probe on half the grid read ΔE00 1.1 darker than the
// render it stood for.
PhotoCrop probe_grid_for(const PhotoCrop& render_grid) {
  constexpr int kProbeSide = 320;
  const int longer = std::max(render_grid.width, render_grid.height);
  const int coarser = std::max(1, (longer + kProbeSide - 1) / kProbeSide);
  PhotoCrop g = render_grid;
  g.px_per_panel_px *= coarser;
  g.width = (render_grid.width + coarser - 1) / coarser;
  g.height = (render_grid.height + coarser - 1) / coarser;
  return g;
}

Bounds3f control_point_bounds(const Feather& feather) {
  Bounds3f b;
  for (const Curve& c : feather.curves)
    for (const ControlPoint& p : c.points) b.extend(p.p);
  return b;
}
}  // namespace

PhotoComparison compare_with_photo(const Image& photo, const Layout& layout, const FeatherLayout& picked,
                                   const Feather& feather, const DomeRig& rig, ViewSpec view, int size,
                                   const FidelitySettings& settings, const CalibrationSettings& calibration) {
  PhotoComparison c;
  c.settings = settings;
  c.crop = crop_for(layout, picked, size);
  if (photo.width != layout.image_width || photo.height != layout.image_height)
    throw Error("the photo is " + std::to_string(photo.width) + "x" + std::to_string(photo.height) +
                " but its layout was made from a " + std::to_string(layout.image_width) + "x" +
                std::to_string(layout.image_height) + " image");
  Image photo_panel = crop_photo(photo, c.crop);
  const glm::vec3 bg = background_colour(photo, photo_panel);
  c.render_grid = render_grid_for(c.crop);
  c.render_spp = render_spp_for(view.spp, c.crop, c.render_grid);
  view.width = c.render_grid.width;
  view.height = c.render_grid.height;
  view.spp = c.render_spp;
  view.camera = crop_camera(picked, c.render_grid);
  SceneOptions so;
  so.backdrop = photo_backdrop(bg, picked, c.render_grid, control_point_bounds(feather));
  // Expose like the photo: the card (its albedo proportional to the photo's
  // background) develops to the background's own level, so to its colour.
  view.card_level = luminance(bg);
  // On a light background the albedo texture is relative to the paper, which the
  // card stands for: the vane must look that many times the card.
  // On a dark one it is the photo's own colour, inverted through the same table over
  // the card that stands for the cloth.
  view.photo_card = so.backdrop.albedo;
  view.photo_texture_absolute = layout.background != "light";
  c.regions = crop_regions(picked, c.crop);
  // The photo's backdrop is its background (neighbouring feathers may lie in its
  // ring); a render's card is alone in its panel.
  const MeasuredPanel photo_measured = measure_panel(photo_panel, c.regions, settings, bg);
  c.measured.push_back(photo_measured);
  const PhotoCrop probe_grid = probe_grid_for(c.render_grid);
  // Each mode's colour calibrated on its own scene (colour_calibration.h), then
  // rendered; a feather without a photo texture has nothing to calibrate. A probe
  // is held to the photo seen through its own grid, measured over the photo's
  // feather mask, so that a coarse pixel mixes a feather's edge with the card in
  // both alike.
  CalibrationSettings cs = calibration;
  if (feather.albedo.texture.empty()) cs.probes = 0;
  glm::vec3 photo_mean(0.0f);
  if (cs.probes > 0) {
    const Image seen = show_on_panel(crop_photo(photo, probe_grid), probe_grid, c.crop);
    photo_mean = mean_over_mask(gaussian_blur(seen, settings.blur_sigma_px), photo_measured.feather);
  }
  c.panels.push_back({std::move(photo_panel), "photo"});
  const ModeScenes scenes(feather, so);
  for (const Scene* s : scenes.both()) {
    const Scene& scene = *s;
    const ShadingMode mode = scene.options().mode;
    ViewSpec probe = view;
    probe.width = probe_grid.width;
    probe.height = probe_grid.height;
    probe.camera = crop_camera(picked, probe_grid);
    probe.spp = std::max(1, view.spp / std::max(1, cs.spp_divisor));
    probe.allocation = SampleAllocation::Uniform;
    probe.adaptive = false;
    probe.denoise = false;  // read for its mean (one sample a pixel has no variance to filter by)
    probe.progress = false;
    const auto probe_mean = [&](const glm::vec3& gain) {
      probe.photo_gain = gain;
      // Blurred as measure_panel blurs, averaged over the photo's mask as
      // compare_panels averages (its render_mean), without the render's own mask.
      const Image shown = show_on_panel(render_view(scene, rig, probe), probe_grid, c.crop);
      return mean_over_mask(gaussian_blur(shown, settings.blur_sigma_px), photo_measured.feather);
    };
    c.calibration.push_back(calibrate_colour(probe_mean, photo_mean, cs));
    ViewSpec v = view;
    v.photo_gain = c.calibration.back().gain;
    c.panels.push_back({show_on_panel(render_view(scene, rig, v), c.render_grid, c.crop), to_string(mode)});
    c.measured.push_back(measure_panel(c.panels.back().image, c.regions, settings));
    if (!feather.albedo.texture.empty()) c.inversion.push_back(view_material(feather, v, mode).count_inversion());
  }
  for (std::size_t i = 1; i < c.measured.size(); ++i)
    c.fidelity.push_back(compare_panels(c.measured[0], c.measured[i], c.regions));
  return c;
}

Image comparison_image(const PhotoComparison& c) { return side_by_side(c.panels); }

Image fidelity_image(const PhotoComparison& c) {
  std::vector<Panel> tiles;
  for (std::size_t i = 1; i < c.panels.size(); ++i) {
    tiles.push_back({mask_picture(c.measured[0], c.measured[i], c.regions),
                     c.panels[i].label + ": silhouettes (red photo only, blue render only)"});
    tiles.push_back({difference_picture(c.measured[0], c.measured[i], c.regions),
                     c.panels[i].label + ": pixel dE2000, white at 20 and above"});
  }
  return contact_sheet(tiles, 2, "fidelity against the photo");
}

nlohmann::json fidelity_json(const PhotoComparison& c) {
  nlohmann::json j;
  j["settings"] = to_json(c.settings);
  j["panel"] = {{"width", c.crop.width},
                {"height", c.crop.height},
                {"photo_origin_px", {c.crop.origin_px.x, c.crop.origin_px.y}},
                {"photo_px_per_panel_px", c.crop.px_per_panel_px}};
  j["panel"]["render_grid"] = {{"width", c.render_grid.width},
                                {"height", c.render_grid.height},
                                {"photo_px_per_render_px", c.render_grid.px_per_panel_px},
                                {"spp", c.render_spp}};
  for (std::size_t i = 1; i < c.panels.size(); ++i) {
    j[c.panels[i].label] = to_json(c.fidelity[i - 1]);
    if (i - 1 < c.calibration.size()) {
      const ColourCalibration& cal = c.calibration[i - 1];
      nlohmann::json probes = nlohmann::json::array();
      for (const CalibrationProbe& p : cal.probes)
        probes.push_back({{"gain", {p.gain.x, p.gain.y, p.gain.z}},
                          {"render_mean_rgb", {p.render_mean.x, p.render_mean.y, p.render_mean.z}},
                          {"mean_colour_de2000", p.de2000}});
      j[c.panels[i].label]["calibration"] = {{"gain", {cal.gain.x, cal.gain.y, cal.gain.z}}, {"probes", probes}};
    }
    if (i - 1 < c.inversion.size()) {
      const InversionCounts& n = c.inversion[i - 1];
      j[c.panels[i].label]["inversion"] = {{"texels", n.texels}, {"medulla", n.medulla}, {"clamped", n.clamped}};
    }
  }
  return j;
}

}  // namespace plumage
