#pragma once
// A bird's wing as a scene of placed feathers (docs/wing.md): the flight feathers
// and two rows of coverts along the wing's bones, each feather's parameters
// interpolated between key feathers in the manner of Chen, Xu, Guo and Shum 2002
// ("Modeling and rendering of realistic feathers", SIGGRAPH: a coat grown from a
// few key feathers by interpolating their parameters), spread or folded, overlapping
// as a real wing's feathers do; optionally the other wing as its mirror image,
// sharing the same feathers.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"
#include "plumage/common/scene_format.h"
#include "plumage/generator/feather_params.h"

namespace plumage {

// Parameters a + t (b - a), t in [0, 1]: every number interpolated (counts
// rounded), each profile on the union of the two profiles' knots; the switches
// (afterfeather on, the split seed) and names are a's below t = 0.5 and b's from it.
FeatherParams blend_params(const FeatherParams& a, const FeatherParams& b, double t);

// The rows of a wing. Remiges: primaries on the hand, secondaries on the forearm;
// coverts: a row over the remiges' bases (greater) and one over theirs (median).
enum class WingRow { Primary, Secondary, GreaterCovert, MedianCovert };
const char* to_string(WingRow row);

struct WingOptions {
  std::string preset = "rock-dove";  // the wing's species (wing_presets())
  std::uint64_t seed = 1;
  double fold = 0;    // 0 spread .. 1 folded: the elbow and wrist joints close
  bool pair = false;  // add the other wing, the mirror image sharing every feather
  // Key feathers taken from analysed feathers (a sheet's layout.json through
  // layout_to_params) instead of the preset's: the long ones (at least 40 % of the
  // longest) are the remex keys by length rank, outermost primary the longest; the
  // bones and the coverts scale with them, the coverts take the shortest one's
  // colour. Fewer than two: the preset's keys.
  std::vector<FeatherParams> keys;
};

// One feather of the wing: its row, number in the row (1 = outermost primary P1 is
// at the wrist: ornithology counts primaries outward from the wrist and secondaries
// inward from it), its parameters, and where it is placed on the right wing.
struct WingFeather {
  WingRow row;
  int number;
  std::string name;      // "P1", "S3", "GC12", "MC4"
  FeatherParams params;
  glm::mat4 to_world;    // the right wing's placement (wing along +X, tail toward -Y, dorsal +Z)
};

struct Wing {
  std::vector<WingFeather> feathers;
  glm::mat4 mirror;       // right wing -> left wing (--pair): x -> -x about the body's midline
  std::string description;
};

// The wing presets' names ("rock-dove"); docs/wing.md gives their sources.
std::vector<std::string> wing_presets();
// Throws plumage::Error for an unknown preset or fold outside [0, 1].
Wing build_wing(const WingOptions& options);

// The scene of `wing`: its distinct feathers as .fcurves files named
// `folder`/NAME.fcurves (paths in the scene relative to the scene's folder, as
// written in `folder_in_scene`), placed once (and, with options.pair, again mirrored).
FeatherScene wing_scene(const Wing& wing, const WingOptions& options, const std::string& folder_in_scene);

}  // namespace plumage
