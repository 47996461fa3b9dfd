#pragma once
// Run time against error (`plumage bench`): a high-sample reference per shading
// mode, then a ladder of sample counts rendered with an independent seed, each
// timed and compared with the reference. Unbiased Monte Carlo has RMSE ~ N^-1/2,
// so on log-log axes error against time falls with slope -0.5; a slope near 0
// over the top of the ladder means the error has hit a floor (bias).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plumage/common/feather.h"
#include "plumage/common/image.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/scene.h"

namespace plumage {

struct LadderPoint {
  std::string mode;
  int spp = 0;
  double seconds = 0;      // wall clock of the fastest repeat
  double cpu_seconds = 0;  // user + system CPU time of the process over that repeat (all threads)
  double rmse = 0;
  double rel_mse = 0;
};

struct LadderSpec {
  std::vector<ShadingMode> modes{ShadingMode::Hair, ShadingMode::Substructure};
  std::vector<int> spp{1, 2, 4, 8, 16, 32, 64, 128, 256};
  int reference_spp = 4096;
  std::uint64_t reference_seed = 0x9e3779b97f4a7c15ull;  // never equal to the ladder's seed
  int repeats = 1;  // renders per rung; the fastest time counts (error from the first)
  BackdropSpec backdrop{true, glm::vec3(0.8f)};
  // The accuracy study (docs/substructure.md, "Explicit reference"): when set, one
  // reference rendered in this mode serves every mode, so a rung's error is its
  // noise plus its mode's model error against that geometry. Such errors level off
  // at the model error by design: biased_modes() says nothing about such a run.
  std::optional<ShadingMode> reference_mode;
};

// Root mean square difference over all channels; throws plumage::Error when the
// sizes differ.
double rmse(const Image& a, const Image& reference);
// Mean over pixels and channels of (a - ref)^2 / (ref^2 + 1e-2), which weighs
// dark and bright pixels alike (the 1e-2 keeps black pixels finite).
double relative_mse(const Image& a, const Image& reference);

// Least-squares slope of log(y) against log(x); NaN with fewer than two usable
// (positive, finite) points or no spread in x.
double loglog_slope(const std::vector<double>& x, const std::vector<double>& y);

// The slope of log RMSE against log seconds over the upper half of one mode's
// rungs (ordered by spp), where an error floor shows.
double upper_half_slope(const std::vector<LadderPoint>& points, const std::string& mode);

// Modes whose upper-half slope is above `max_slope` (or could not be fitted), each
// as "MODE: slope S over spp A..B"; empty when every mode's error keeps falling.
std::vector<std::string> biased_modes(const std::vector<LadderPoint>& points, double max_slope = -0.3);

// Renders the references (one per mode, or the one of spec.reference_mode) and the
// ladder. `view.seed` seeds the ladder; the
// reference uses spec.reference_seed (an error must be thrown if they are equal:
// shared samples would hide the error being measured).
std::vector<LadderPoint> run_ladder(const Feather& feather, const DomeRig& rig, const ViewSpec& view,
                                    const LadderSpec& spec);

// "mode,spp,seconds,rmse,relative_mse,cpu_seconds" and one row per point.
std::string ladder_csv(const std::vector<LadderPoint>& points);

// Log-log plot of RMSE against seconds: decade ticks and labels, one coloured
// line per mode with its name, and a dashed slope -0.5 reference line.
Image plot_ladder(const std::vector<LadderPoint>& points, int width = 640, int height = 480);

}  // namespace plumage
