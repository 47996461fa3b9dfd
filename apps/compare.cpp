// `plumage compare`: one feather rendered with hair shading and with the
// substructure technique (Baron et al. 2021) under the same camera, lights,
// samples and exposure, side by side and labelled, after the photograph when one
// is given; or, with --light-sequence, one dome LED at a time (the paper's Fig. 5)
// as a labelled contact sheet per shading mode (docs/substructure.md).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "command.h"
#include "substructure_options.h"
#include "view_options.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/pipeline/feather_scene.h"
#include "plumage/pipeline/photo_comparison.h"
#include "plumage/renderer/panel_layout.h"

namespace plumage::cli {
namespace {

struct Options {
  std::string input, output, photo;
  ViewOptions view{"320x480", "WIDTHxHEIGHT of one panel, e.g. 320x480"};
  bool light_sequence = false;
  int columns = 5;
  SubstructureOverrides substructure;
};

std::filesystem::path with_suffix(const std::filesystem::path& p, const std::string& suffix) {
  return p.parent_path() / (p.stem().string() + suffix + p.extension().string());
}

// `plumage compare scene.fscene`: the placed feathers in hair and substructure shading.
int run_compare_scene(const Options& o, ViewSpec view) {
  if (o.light_sequence) throw UsageError("--light-sequence works on one feather; compare a .fcurves file for it");
  if (o.view.cull) throw UsageError("--cull works on one feather; leave it out for a .fscene");
  LoadedScene loaded = load_scene(o.input);
  o.view.apply_scene(loaded.scene, view);
  const DomeRig rig = o.view.read_rig_for(view, o.input);
  for (Feather& f : loaded.feathers) o.substructure.apply(f);
  Image photo;
  if (!o.photo.empty()) photo = read_image(o.photo);
  std::vector<Panel> panels;
  if (!photo.empty()) panels.push_back({scale_to_height(photo, view.height), "photo"});
  for (Panel& p : render_scene_both_modes(loaded, o.view.scene_options(view, rig), rig, view)) panels.push_back(std::move(p));
  write_image(o.output, side_by_side(panels));
  if (!global_options().quiet) std::cerr << "wrote " << o.output << "\n";
  return 0;
}

int run_compare(const Options& o) {
  const ViewSpec view = o.view.view_spec(o.input, !global_options().quiet);
  if (const std::string bad = image_output_problem(o.output, {".png", ".exr", ".jpg", ".tif"}); !bad.empty())
    throw UsageError(bad);
  if (std::filesystem::path(o.input).extension() == ".fscene") return run_compare_scene(o, view);

  const DomeRig rig = o.view.read_rig();
  Feather feather = read_fcurves(o.input);
  o.substructure.apply(feather);
  // Read the photo before the (long) renders so a bad path fails at once.
  Image photo;
  if (!o.photo.empty()) photo = read_image(o.photo);

  // With --cull both modes leave out the same curves: those no panel's camera and LEDs need.
  SceneOptions so = o.view.scene_options(view, rig);
  if (!o.light_sequence) {
    std::vector<Panel> panels;
    if (!photo.empty()) panels.push_back({scale_to_height(photo, view.height), "photo"});
    for (Panel& p : render_both_modes(feather, so, rig, view)) panels.push_back(std::move(p));
    write_image(o.output, side_by_side(panels));
    if (!global_options().quiet) std::cerr << "wrote " << o.output << "\n";
    return 0;
  }
  FileBatch outputs;  // one sheet per shading mode: both or neither
  std::vector<std::filesystem::path> written;
  for (const Panel& sheet : light_sequence_sheets(feather, so, rig, view, o.columns)) {
    const std::string& name = sheet.label;
    const std::filesystem::path out = with_suffix(o.output, std::string("_") + name);
    write_image(outputs, out, sheet.image);
    written.push_back(out);
  }
  outputs.commit();
  if (!global_options().quiet)
    for (const auto& out : written) std::cerr << "wrote " << out.string() << "\n";
  return 0;
}

const Registration kCompare{
    "compare", "Render a feather with hair and substructure shading side by side (and beside a photo)",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.footer(
          "Both panels share the camera (auto-framed top view unless --camera-pos), lights, samples, seed\n"
          "and exposure; --cull leaves out the curves neither panel can show (docs/skip-work.md).\n"
          "A .fscene compares its placed feathers (docs/scene-format.md); its camera and lights apply where no flag sets them.\n"
          "Example: plumage compare feather.fcurves --photo feather.jpg -o side_by_side.png --spp 64\n"
          "         plumage compare feather.fcurves --light-sequence --resolution 160x240 -o seq.png\n"
          "See docs/substructure.md.");
      sub.add_option("input", o->input, "Feather curve file (.fcurves) or scene of many feathers (.fscene)")->required();
      o->view.record_given(sub);
      sub.add_option("-o,--output", o->output, "Output image (.png sRGB or .exr linear); with --light-sequence, "
                                               "NAME_hair.png and NAME_substructure.png")->required();
      sub.add_option("--photo", o->photo, "Photograph of the feather, shown first (scaled to the panel height)");
      o->view.add_to(sub, "Size of one panel WIDTHxHEIGHT",
                     "Dome LEDs that are on (with --light-sequence: the LEDs to step through)");
      CLI::Option* sequence =
          sub.add_flag("--light-sequence", o->light_sequence, "One LED at a time: a labelled contact sheet per shading mode")
              ->excludes("--photo");
      sub.add_option("--columns", o->columns, "With --light-sequence: contact sheet tiles per row")
          ->capture_default_str()
          ->check(in_range(1, 1000))
          ->needs(sequence);
      o->substructure.add_to(sub);
      return [o] { return run_compare(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
