#pragma once
// The whole chain of DESIGN §1 on one photo, as `plumage photo-to-feather` runs it:
// analyze (layout.json, overlay.png, the albedo), generate (feather.fcurves,
// feather.albedo.png, preview.png), compare (comparison.png and, when asked,
// fidelity.png: the picked feather's crop | hair | substructure in one pose) and
// summary.json (counts, settings, fidelity, stage times, files, warnings). OUTDIR
// is all-or-nothing: a run that fails at any stage leaves every file in it as it
// was (a previous run's results included), and a folder this call created is
// removed again; a run that succeeds leaves exactly its own artifacts there.
#include <filesystem>
#include <functional>
#include <string>

#include "plumage/analysis/analyze.h"
#include "plumage/pipeline/colour_calibration.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/feather_render.h"

namespace plumage {

struct PhotoToFeatherSettings {
  std::filesystem::path photo, outdir;
  AnalyzeOptions analyze;       // scale, grid, which feather
  ViewSpec view;                // sampling, lights, threads; its seed seeds the generator too
  DomeRig rig;
  int size = 672;               // panels' longer side (pixels)
  bool fidelity_image = false;  // also write fidelity.png
  CalibrationSettings calibration;  // of each render's colour against the photo's
};

// After each finished stage: its name, wall seconds and a one-line account.
using StageReport = std::function<void(const std::string& stage, double seconds, const std::string& what)>;
// Something a person should know (the feather picked from a sheet, values the generator replaced).
using Notice = std::function<void(const std::string& note)>;

// Throws plumage::Error "photo-to-feather: stage 'NAME' failed: ..." when a stage
// fails, or naming OUTDIR when it is not a folder.
void photo_to_feather(const PhotoToFeatherSettings& settings, const StageReport& report = {},
                      const Notice& warn = {});

}  // namespace plumage
