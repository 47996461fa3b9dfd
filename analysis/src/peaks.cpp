// Peaks of a 1-D profile and how far each stands out (its prominence). Of
// maxima of equal height (a plateau with a ripple, a smoothed profile's ties)
// the first stands out by the profile's own descent, the later ones only by
// the dip since the one before, so a flat top is one peak, not one per ripple.
#include <algorithm>

#include "peaks.h"

namespace plumage::analysis {

std::vector<Peak> profile_peaks(const std::vector<double>& v) {
  std::vector<Peak> peaks;
  const int n = int(v.size());
  for (int i = 1; i + 1 < n; ++i) {
    if (!(v[i] >= v[i - 1] && v[i] > v[i + 1])) continue;
    double low_before = v[i], low_after = v[i];
    int k = i - 1;
    while (k >= 0 && v[k] == v[i]) --k;  // its own flat top
    for (; k >= 0 && v[k] < v[i]; --k) low_before = std::min(low_before, v[k]);
    for (k = i + 1; k < n && v[k] <= v[i]; ++k) low_after = std::min(low_after, v[k]);
    peaks.push_back({i, v[i] - std::max(low_before, low_after)});
  }
  return peaks;
}

}  // namespace plumage::analysis
