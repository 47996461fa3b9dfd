#pragma once
// A row of drawn feathers analysed as a photo: every analysed feather is one of
// them, found from its own quill (its calamus within 3 % of the length of the
// drawn one's, its shaft nearer that feather's rachis than any other's over
// nine tenths of its length), none found twice; or the row is reported as
// several feathers (docs/analysis.md, "Shingled rows" and "Sheets").
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "plumage/analysis/analyze.h"
#include "plumage/common/error.h"
#include "plumage/layout/layout.h"
#include "synthetic_feather.h"

namespace plumage::synthetic {

// A point of an analysed feather's shaft in photo pixels, t = 0 its calamus, 1 its tip.
inline glm::dvec2 shaft_px(const FeatherLayout& f, double t) {
  return apply(f.image_from_feather, f.shaft_mm.eval(t));
}

struct RowOutcome {
  bool reported = false;  // refused or skipped as several feathers
  std::string message;    // why, when reported
  int found = 0;          // analysed feathers, each checked against `row`
  std::vector<int> matched;  // per drawn feather, how many analysed feathers are it
  Layout layout;
};

inline RowOutcome analyse_row(const std::filesystem::path& photo, const std::vector<SyntheticFeather>& row) {
  RowOutcome out;
  PhotoAnalysis A;
  try {
    A = analyze_photo(photo, AnalyzeOptions{});
  } catch (const Error& e) {
    out.reported = true;
    out.message = e.what();
    return out;
  }
  out.layout = A.layout;
  const Layout& L = out.layout;
  for (const SkippedRegion& r : L.skipped)
    if (r.reason != "split_row") out.reported = true, out.message += r.message;
  std::vector<int> matched(row.size(), 0);
  for (const FeatherLayout& f : L.feathers) {
    const glm::dvec2 c = shaft_px(f, 0.0);
    std::size_t k = 0;
    for (std::size_t j = 1; j < row.size(); ++j)
      if (glm::length(row[j].calamus - c) < glm::length(row[k].calamus - c)) k = j;
    const SyntheticFeather& t = row[k];
    ++matched[k];
    EXPECT_LT(glm::length(c - t.calamus), 0.03 * t.length) << "feather " << f.id;
    for (int i = 0; i <= 18; ++i) {
      const glm::dvec2 p = shaft_px(f, i / 20.0);
      auto off_rachis = [&](const SyntheticFeather& g) {
        return glm::length(p - (g.calamus + std::clamp(g.along(p.x, p.y), 0.0, g.length) * g.dir()));
      };
      const double own = off_rachis(t);
      for (std::size_t j = 0; j < row.size(); ++j) {
        if (j != k) {
          EXPECT_LT(own, std::max(off_rachis(row[j]), 0.03 * t.length)) << "feather " << f.id << " at t = " << i / 20.0;
        }
      }
    }
  }
  for (std::size_t j = 0; j < row.size(); ++j) EXPECT_LE(matched[j], 1) << "drawn feather " << j;
  out.found = int(L.feathers.size());
  out.matched = matched;
  return out;
}

}  // namespace plumage::synthetic
