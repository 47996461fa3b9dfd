// The rules both sides of layout.json apply (rules.h).
#include "plumage/layout/rules.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "plumage/common/median.h"
#include "plumage/common/number_text.h"

namespace plumage {

double barb_spacing_prior_mm(double length_mm) {
  return std::clamp(0.25 + 0.002 * length_mm, 0.25, 0.75);
}

BarbSpacingReading resolved_barb_spacing(const FeatherLayout& f, VaneSide side) {
  const VaneProfile& v = side == VaneSide::Left ? f.left : f.right;
  BarbSpacingReading out;
  std::vector<double> values;
  for (std::size_t i = 0; i < f.stations_t.size(); ++i)
    if (v.barb_spacing_confidence[i] >= kLayoutMinConfidence && v.barb_spacing_mm[i] > 0 &&
        f.stations_t[i] >= v.afterfeather_to_t)
      values.push_back(v.barb_spacing_mm[i]);
  // A side's spacing is the median of its trusted stations, but only when there are
  // enough of them for a median to reject an outlier: with one or two, a single
  // harmonic mistaken for the period (twice the true spacing, say) would halve
  // the barb count of the whole vane.
  constexpr std::size_t kMinSpacingStations = 3;
  if (values.size() < kMinSpacingStations) return out;
  // The photo resolves barbs only when (docs/analysis.md, "Barb density") the
  // period spans at least kMinPeriodPx pixels, the stations agree (median
  // absolute deviation within kMaxSpread of the median), and the spacing is
  // within a factor kPriorFactor of the prior: a "period" of texture, bars or
  // harmonics at a scale that cannot resolve barbs fails one of the three.
  constexpr double kMinPeriodPx = 2.5, kMaxSpread = 0.25, kPriorFactor = 4.0;
  const double prior = barb_spacing_prior_mm(f.length_mm);
  // Photo millimetres per pixel: the length of a column of the similarity.
  const double mm_per_px = glm::length(glm::dvec2(f.feather_from_image[0]));
  const double m = median(values);
  std::vector<double> dev;
  for (double x : values) dev.push_back(std::fabs(x - m));
  const double spread = median(dev) / m;
  std::ostringstream why;
  if (std::isfinite(mm_per_px) && mm_per_px > 0 && m / mm_per_px < kMinPeriodPx)
    why << "its period " << num(m / mm_per_px) << " px is under " << kMinPeriodPx << " px";
  else if (spread > kMaxSpread)
    why << "its stations disagree (spread " << std::lround(100 * spread) << " % of the median)";
  else if (m < prior / kPriorFactor || m > prior * kPriorFactor)
    why << num(m) << " mm is not within x" << kPriorFactor << " of the prior " << num(prior) << " mm";
  if (why.str().empty())
    out.mm = m;
  else
    out.refused = why.str();
  return out;
}

}  // namespace plumage
