#pragma once
// The rules both sides of layout.json apply to what it holds (docs/layout-format.md):
// photo analysis, which writes it and draws what is trusted on its overlay, and
// the generator, which builds a feather from it. One home, so that what the
// overlay shows as trusted is what the generator uses.
#include <optional>
#include <string>

#include "plumage/common/feather.h"
#include "plumage/layout/layout.h"

namespace plumage {

// The shaft lengths a feather may have, calamus base to tip: the one rule the
// parameter validator, the layout reader and the photo analysis share.
inline constexpr double kMinShaftLengthMm = 1.0;
inline constexpr double kMaxShaftLengthMm = 2000.0;

// Measurements with confidence below this are not trusted (docs/layout-format.md).
inline constexpr double kLayoutMinConfidence = 0.5;

// Barb spacing along the rachis (mm, each side) assumed for a feather of this
// shaft length when the photo does not resolve its barbs (docs/analysis.md,
// "Barb density": 0.25 mm + 0.2 % of the length, within [0.25, 0.75] mm).
double barb_spacing_prior_mm(double length_mm);

// One side's barb spacing, when the photo resolves its barbs (docs/analysis.md,
// "Barb density"): the median of its stations trusted (confidence >=
// kLayoutMinConfidence) above its downy base, when there are at least three of
// them, the period spans at least 2.5 photo pixels, they agree (median absolute
// deviation within 25 % of the median) and it is within a factor 4 of
// barb_spacing_prior_mm. `refused` says which test failed, for a person; both
// are empty when too few stations are trusted.
struct BarbSpacingReading {
  std::optional<double> mm;
  std::string refused;
};
BarbSpacingReading resolved_barb_spacing(const FeatherLayout& layout, VaneSide side);

}  // namespace plumage
