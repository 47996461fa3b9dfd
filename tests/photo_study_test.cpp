// The photo study's counts (docs/analysis.md, "Photo study"): every photo in
// ../shared/photos is analysed, and the feathers found are held to the counts by
// eye in data/photo-study/counts.json. Skipped when the photos are absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/generator/analysis/analyze.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

const nlohmann::json& counts() {
  static const nlohmann::json c =
      nlohmann::json::parse(read_file(fs::path(PLUMAGE_DATA_DIR) / "photo-study" / "counts.json"));
  return c.at("photos");
}

PhotoAnalysis analyse(const std::string& name) {
  AnalyzeOptions opt;
  const auto& c = counts().at(name);
  if (c.contains("grid_mm")) opt.grid_mm = c.at("grid_mm").get<double>();
  return analyze_photo(fs::path(PLUMAGE_SHARED_DIR) / "photos" / name, opt);
}

}  // namespace

TEST(PhotoStudy, EveryPhotoIsAnalysed) {
  const fs::path dir = fs::path(PLUMAGE_SHARED_DIR) / "photos";
  if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir << " (shared photos absent)";
  int photos = 0;
  for (const auto& [name, c] : counts().items()) {
    if (!fs::exists(dir / name)) continue;
    PhotoAnalysis A;
    ASSERT_NO_THROW(A = analyse(name)) << name;
    EXPECT_FALSE(A.layout.feathers.empty()) << name;
    // Ids are shared by analysed and skipped regions, one each, 1..N.
    std::vector<int> ids;
    for (const auto& f : A.layout.feathers) ids.push_back(f.id);
    for (const auto& s : A.layout.skipped) ids.push_back(s.id);
    std::sort(ids.begin(), ids.end());
    for (std::size_t i = 0; i < ids.size(); ++i) EXPECT_EQ(ids[i], int(i) + 1) << name;
    ++photos;
  }
  EXPECT_EQ(photos, 6);
}

// Exact where the analysis holds: one region per feather, none skipped.
TEST(PhotoStudy, SpoonbillAndPinkCountsAreExact) {
  for (const char* name : {"spoonbill-wing-sheet.png", "pink-contour-feather.jpg"}) {
    if (!fs::exists(fs::path(PLUMAGE_SHARED_DIR) / "photos" / name)) GTEST_SKIP() << "shared photos absent";
    const PhotoAnalysis A = analyse(name);
    EXPECT_EQ(int(A.layout.feathers.size()), counts().at(name).at("feathers").get<int>()) << name;
    EXPECT_TRUE(A.layout.skipped.empty()) << name;
  }
}

// Not exact yet (docs/analysis.md says why): some small body feathers are
// missed or joined, two of the white downy feathers are one region, two
// overlapping tail feathers are one region (so "no more regions than feathers"
// does not prove that no region is two feathers). Held to what is found now:
// never more regions than feathers by eye, and no fewer than found at this
// writing (peregrine 36 + 3 touching, blue jay 47 + 8 skipped).
TEST(PhotoStudy, PeregrineAndBlueJayFindMostFeathersAndNoMoreRegionsThanFeathers) {
  for (const auto& [name, found] : {std::pair<const char*, int>{"peregrine-falcon-feather-sheet.jpg", 39},
                                    {"blue-jay-feather-sheet.jpg", 55}}) {
    if (!fs::exists(fs::path(PLUMAGE_SHARED_DIR) / "photos" / name)) GTEST_SKIP() << "shared photos absent";
    const PhotoAnalysis A = analyse(name);
    const int regions = int(A.layout.feathers.size() + A.layout.skipped.size());
    const int eye = counts().at(name).at("feathers").get<int>();
    EXPECT_LE(regions, eye) << name;
    EXPECT_GE(regions, found) << name;
  }
}
