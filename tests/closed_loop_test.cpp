// The closed-loop accuracy study of photo analysis (issue #6, closed_loop.h):
// every drawn feather on white and on black must meet the five bounds.
// With PLUMAGE_CLOSED_LOOP_REPORT=DIR set, the study also writes its table and
// overlays there (scripts/closed_loop.sh puts them into docs/analysis.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "closed_loop.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/image.h"

using namespace plumage;
using namespace plumage::closed_loop;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("plumage_closed_loop_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Half-size copy (2x2 box), for small overlay images in the docs.
Image half_size(const Image& in) {
  Image out(in.width / 2, in.height / 2, 3);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      out.set_rgb(x, y, 0.25f * (in.rgb(2 * x, 2 * y) + in.rgb(2 * x + 1, 2 * y) +
                                 in.rgb(2 * x, 2 * y + 1) + in.rgb(2 * x + 1, 2 * y + 1)));
  return out;
}

void write_report(const fs::path& dir, const std::vector<CaseResult>& rs, const StudyOptions& o,
                  const Bounds& b) {
  fs::create_directories(dir);
  write_file_atomic(dir / "closed-loop-table.md", report_markdown(rs, o, b));
  // Three overlays: the worst shaft on white, the worst angle on black, and the lowest IoU.
  std::size_t worst_shaft = 0, worst_angle = 1, worst_iou = 0;
  for (std::size_t i = 0; i < rs.size(); ++i) {
    if (!rs[i].dark && rs[i].shaft > rs[worst_shaft].shaft) worst_shaft = i;
    if (rs[i].dark && rs[i].angle_deg > rs[worst_angle].angle_deg) worst_angle = i;
    if (rs[i].iou < rs[worst_iou].iou) worst_iou = i;
  }
  int n = 1;
  for (std::size_t i : {worst_shaft, worst_angle, worst_iou})
    write_image(dir / ("closed-loop-" + std::to_string(n++) + ".jpg"), half_size(rs[i].overlay));
}

}  // namespace

TEST(ClosedLoop, TwentyRenderedFeathersOnWhiteAndBlackMeetTheBounds) {
  StudyOptions o;
  o.work_dir = temp_dir("study");
  // PLUMAGE_CLOSED_LOOP_ONLY=K runs feather K alone and keeps its overlays (debugging).
  if (const char* k = std::getenv("PLUMAGE_CLOSED_LOOP_ONLY")) o.only = std::atoi(k), o.keep_overlays = true;
  const Bounds b;
  const std::vector<CaseResult> rs = run_study(o);
  ASSERT_EQ(rs.size(), o.only ? 2u : 2u * o.feathers);
  for (const CaseResult& r : rs) {
    SCOPED_TRACE("feather " + std::to_string(r.feather) + " on " + (r.dark ? "black" : "white") +
                 " (" + r.summary + "), " + r.photo.string());
    EXPECT_LE(r.shaft, b.shaft);
    EXPECT_LE(r.angle_deg, b.angle_deg);
    EXPECT_LE(r.spacing, b.spacing);
    EXPECT_LE(r.width, b.width);
    EXPECT_GE(r.iou, b.iou);
    // Enough compared stations that a median means something.
    EXPECT_GE(r.angle_used, 4);
    EXPECT_GE(r.spacing_used, 4);
    EXPECT_GE(r.width_used, 4);
  }
  std::printf("%s", report_markdown(rs, o, b).c_str());
  if (const char* dir = std::getenv("PLUMAGE_CLOSED_LOOP_REPORT")) write_report(dir, rs, o, b);
  if (HasFailure() || o.only)
    std::printf("photos kept for inspection in %s\n", o.work_dir.string().c_str());
  else
    fs::remove_all(o.work_dir);
}

// The study can fail: a wrong truth or a much worse photo breaks the bounds.
TEST(ClosedLoop, PerturbedTruthOrStrongerDegradationFails) {
  StudyOptions o;
  o.work_dir = temp_dir("perturbed");
  const Bounds b;
  const FeatherParams p = draw_params(1, o.seed, o.long_side_px).front();
  const CaseResult clean = run_case(p, 1, false, o);
  EXPECT_TRUE(clean.passes(b));

  StudyOptions shifted = o;
  shifted.perturb_truth_shaft_px = 0.015 * clean.length_mm / clean.mm_per_px;
  EXPECT_GT(run_case(p, 1, false, shifted).shaft, b.shaft);

  StudyOptions steeper = o;
  steeper.perturb_truth_angle = 1.15;
  EXPECT_GT(run_case(p, 1, false, steeper).angle_deg, b.angle_deg);

  StudyOptions blurred = o;
  blurred.degrade.blur_sigma_px = 6.0;
  blurred.degrade.noise_sigma = 0.08;
  EXPECT_FALSE(run_case(p, 1, false, blurred).passes(b));
  fs::remove_all(o.work_dir);
}
