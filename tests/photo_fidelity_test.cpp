// photo-to-feather's one pose and its fidelity metrics (apps/pipeline:
// photo_view.h, fidelity.h; docs/analysis.md, "One pose" and "Fidelity"): CIE ΔE
// 2000 against Sharma et al.'s published pairs, the crop's camera against the
// layout's transform, silhouettes and IoU on drawn panels, and the bounds of
// issue 12 on the pink photo, a spoonbill sheet feather and a robin sheet feather (when ../shared has them).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/pipeline/fidelity.h"
#include "plumage/pipeline/photo_view.h"
#include "plumage/analysis/analyze.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/substructure.h"
#include "synthetic_feather.h"

using namespace plumage;
namespace fs = std::filesystem;

TEST(Ciede2000, MatchesSharmasTestPairs) {
  // Sharma, Wu & Dalal (2005), Table 1: pairs 1, 2, 7, 17 and 25.
  struct Pair {
    glm::vec3 a, b;
    double de;
  } pairs[] = {{{50, 2.6772f, -79.7751f}, {50, 0, -82.7485f}, 2.0425},
               {{50, 3.1571f, -77.2803f}, {50, 0, -82.7485f}, 2.8615},
               {{50, 0, 0}, {50, -1, 2}, 2.3669},
               {{50, 2.5f, 0}, {73, 25, -18}, 27.1492},
               {{60.2574f, -34.0099f, 36.2677f}, {60.4626f, -34.1751f, 39.4387f}, 1.2644}};
  for (const Pair& p : pairs) {
    EXPECT_NEAR(ciede2000(p.a, p.b), p.de, 2e-4) << p.a.x << " " << p.a.y << " " << p.a.z;
    EXPECT_NEAR(ciede2000(p.b, p.a), p.de, 2e-4);
  }
  EXPECT_EQ(ciede2000({40, 10, -5}, {40, 10, -5}), 0.0);
}

TEST(Ciede2000, LabOfLinearRgb) {
  const glm::vec3 white = linear_rgb_to_lab(glm::vec3(1.0f));
  EXPECT_NEAR(white.x, 100.0f, 1e-3f);
  EXPECT_NEAR(white.y, 0.0f, 1e-2f);
  EXPECT_NEAR(white.z, 0.0f, 1e-2f);
  EXPECT_NEAR(linear_rgb_to_lab(glm::vec3(0.0f)).x, 0.0f, 1e-4f);
  // Mid grey 18 % is L* 49.5; pure red has a* > 0, pure blue b* < 0.
  EXPECT_NEAR(linear_rgb_to_lab(glm::vec3(0.18f)).x, 49.5f, 0.1f);
  EXPECT_GT(linear_rgb_to_lab({1, 0, 0}).y, 50.0f);
  EXPECT_LT(linear_rgb_to_lab({0, 0, 1}).z, -50.0f);
}

namespace {
// A feather lying at 30 degrees in a 400x300 photo at 0.25 mm/px: feather = R (u, -v) s + t.
FeatherLayout rotated_feather(Layout& layout) {
  layout.image_width = 400, layout.image_height = 300;
  FeatherLayout f;
  const double a = 30.0 * 3.14159265358979 / 180.0, s = 0.25;
  const glm::dvec2 ex = s * glm::dvec2(std::cos(a), std::sin(a)), ey = s * glm::dvec2(std::sin(a), -std::cos(a));
  f.feather_from_image = glm::dmat3x2(ex, ey, glm::dvec2(-30.0, 12.0));
  f.bbox_px = {100, 80, 150, 90};
  f.length_mm = 40;
  return f;
}
}  // namespace

TEST(PhotoView, CameraSeesExactlyTheCrop) {
  Layout layout;
  const FeatherLayout f = rotated_feather(layout);
  const PhotoCrop crop = crop_for(layout, f, 200);
  EXPECT_EQ(std::max(crop.width, crop.height), 200);
  // The box grown by 6 % of its larger side (9 px) each way: 168 x 108 photo pixels.
  EXPECT_NEAR(crop.px_per_panel_px, 168.0 / 200.0, 1e-9);
  EXPECT_NEAR(crop.origin_px.x, 91.0, 0.5 * crop.px_per_panel_px);
  EXPECT_NEAR(crop.origin_px.y, 71.0, 0.5 * crop.px_per_panel_px);
  Bounds3f fb;
  fb.extend({-40, -10, -1}), fb.extend({10, 40, 1});
  const Camera cam(crop_camera(f, crop), crop.width, crop.height, fb);
  // Every panel pixel's ray starts over the feather point its photo pixel shows.
  for (int j : {0, crop.height / 3, crop.height - 1})
    for (int i : {0, crop.width / 2, crop.width - 1})
      for (glm::dvec2 o : {glm::dvec2(0.5, 0.5), glm::dvec2(0.0, 0.0), glm::dvec2(1.0, 1.0)}) {
        const Ray r = cam.generate(float(i + o.x), float(j + o.y));
        const glm::dvec2 want = apply(f.feather_from_image, crop.origin_px + crop.px_per_panel_px * (glm::dvec2(i, j) + o));
        EXPECT_NEAR(r.o.x, want.x, 1e-3) << i << "," << j;
        EXPECT_NEAR(r.o.y, want.y, 1e-3) << i << "," << j;
        EXPECT_NEAR(r.d.z, -1.0f, 1e-6f);
      }
}

TEST(PhotoView, MirroredTransformIsRefused) {
  Layout layout;
  FeatherLayout f = rotated_feather(layout);
  f.feather_from_image[0] = -f.feather_from_image[0];
  const PhotoCrop crop = crop_for(layout, f, 100);
  try {
    crop_camera(f, crop);
    FAIL() << "a mirrored transform was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mirrors"), std::string::npos) << e.what();
  }
}

TEST(PhotoView, RegionsFollowTheOutlineAndTheShaftSplitsTheVanes) {
  // Shaft up the image at u = 200 (feather x = 0.25 (u - 200), y = 0.25 (250 - v)),
  // outline the rectangle u in [170, 240], v in [90, 250].
  Layout layout;
  layout.image_width = 400, layout.image_height = 300;
  FeatherLayout f;
  f.feather_from_image = glm::dmat3x2(glm::dvec2(0.25, 0), glm::dvec2(0, -0.25), glm::dvec2(-50, 62.5));
  f.bbox_px = {170, 90, 70, 160};
  f.outline_px = {{170, 90}, {240, 90}, {240, 250}, {170, 250}};
  for (double y : {-10.0, 0.0, 10.0, 20.0, 30.0, 40.0, 50.0}) f.shaft_mm.control_points().push_back({0.0, y});
  const PhotoCrop crop = crop_for(layout, f, 200);
  const PanelRegions r = crop_regions(f, crop, 3);
  const auto at = [&](double u, double v) {
    const glm::dvec2 p = (glm::dvec2(u, v) - crop.origin_px) / crop.px_per_panel_px;
    return int(r.at(int(p.x), int(p.y)));
  };
  EXPECT_EQ(at(180, 170), 1);  // left of the shaft: the left vane (seen dorsally, tip up)
  EXPECT_EQ(at(230, 170), 2);
  EXPECT_EQ(at(199, 100), 1);
  EXPECT_EQ(at(201, 100), 2);
  // Grown by 3 panel pixels (0.9 photo px each): 1.5 photo px out is in, 5 px out is not.
  EXPECT_NE(at(168.5, 170), 0);
  EXPECT_EQ(at(165, 170), 0);
  EXPECT_EQ(at(200, 255), 0);
  EXPECT_NE(at(200, 251.5), 0);
}

TEST(PhotoView, CropAveragesThePhotoOverEachPanelPixel) {
  // A photo of vertical stripes 1 px wide (0 and 1): panel pixels 2 photo pixels wide average 0.5.
  Image photo(64, 32, 3);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) photo.set_rgb(x, y, glm::vec3(float(x % 2)));
  PhotoCrop crop;
  crop.origin_px = {4, 4};
  crop.px_per_panel_px = 2;
  crop.width = 20, crop.height = 10;
  const Image panel = crop_photo(photo, crop);
  ASSERT_EQ(panel.width, 20);
  for (int x = 0; x < 20; ++x) EXPECT_NEAR(panel.rgb(x, 5).x, 0.5f, 1e-6f);
  crop.origin_px = {4.5, 4};  // half a pixel over: (0.5 * 0 + 1 + 0.5 * 0) / 2 or its complement
  const Image shifted = crop_photo(photo, crop);
  for (int x = 0; x < 20; ++x) EXPECT_NEAR(shifted.rgb(x, 5).x, 0.5f, 1e-6f);
  crop.px_per_panel_px = 1;
  const Image one = crop_photo(photo, crop);  // straddles two stripes equally
  EXPECT_NEAR(one.rgb(3, 3).x, 0.5f, 1e-6f);
}

TEST(PhotoView, TheCardIsReadInsideAScansEdgeLine) {
  // A mid-grey card (as the peregrine sheet's) whose scan has a one-pixel bright
  // line along every edge, with a dark feather across the middle: the card is
  // the grey, not the line, both for the whole photo and near the feather.
  const glm::vec3 card(0.16f, 0.15f, 0.15f), line(0.62f, 0.60f, 0.60f), feather(0.03f);
  Image photo(400, 300, 3, 0.0f);
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x) {
      const bool edge = x == 0 || y == 0 || x == photo.width - 1 || y == photo.height - 1;
      photo.set_rgb(x, y, edge ? line : (y > 140 && y < 160 && x > 20 && x < 380 ? feather : card));
    }
  EXPECT_NEAR(ring_median(photo, [](int, int, const glm::vec3&) { return true; }, 1, 4)->x, card.x, 1e-6f);
  EXPECT_NEAR(ring_median(photo, [](int, int, const glm::vec3&) { return true; })->x, line.x, 1e-6f)
      << "the outermost ring alone is the line";
  // A panel that touches the photo's left edge, as a sheet's first column does.
  PhotoCrop crop;
  crop.origin_px = {0, 100};
  crop.px_per_panel_px = 1;
  crop.width = 400, crop.height = 100;
  const glm::vec3 bg = background_colour(photo, crop_photo(photo, crop));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(bg[k], card[k], 1e-6f) << "channel " << k;
  // Each pixel of a deep frame counts once, even where the frame covers the image.
  Image tiny(3, 2, 3, 0.25f);
  tiny.set_rgb(1, 1, glm::vec3(1.0f));
  int seen = 0;
  ring_median(tiny, [&](int, int, const glm::vec3&) { return ++seen, true; }, 1, 5);
  EXPECT_EQ(seen, 6);
}

TEST(PhotoView, RendersAreTracedOnThePhotosGridWhereItIsCoarser) {
  PhotoCrop shown;
  shown.origin_px = {10.3, 20.6};
  shown.width = 672, shown.height = 180;
  // Panel pixels larger than photo pixels: the panel's own grid.
  shown.px_per_panel_px = 1.5;
  const PhotoCrop same = render_grid_for(shown);
  EXPECT_EQ(same.width, shown.width);
  EXPECT_EQ(same.height, shown.height);
  EXPECT_EQ(same.px_per_panel_px, shown.px_per_panel_px);
  EXPECT_EQ(render_spp_for(8, shown, same), 8);
  // 0.3 photo px per panel px: the crop spans 201.6 x 54 photo pixels, so the
  // photo's own grid (factor 1) has more than kMinRenderSide pixels.
  shown.px_per_panel_px = 0.3;
  const PhotoCrop g = render_grid_for(shown);
  EXPECT_EQ(g.px_per_panel_px, 1.0);
  EXPECT_EQ(g.origin_px, glm::dvec2(10, 20));  // on the photo's pixel corners
  // Covers the crop: 10.3 + 201.6 = 211.9 -> 212; 20.6 + 54 = 74.6 -> 75.
  EXPECT_EQ(g.width, 202);
  EXPECT_EQ(g.height, 55);
  // The panel's samples gathered there would be 8 x (672 x 180) / (202 x 55) = 87;
  // a traced pixel needs a panel pixel's noise, not their budget: at most 2 x 8.
  EXPECT_EQ(render_spp_for(8, shown, g), 8 * kGridSppFactor);
  EXPECT_EQ(render_spp_for(1, shown, g), kGridSppFactor);
  EXPECT_EQ(render_spp_for(4096, shown, g), 4096);  // never fewer than asked, never more than 4096 unless asked
  // Where the ratio is under the factor the panel's budget is what it spends.
  PhotoCrop near = g;
  near.width = 600, near.height = 170;  // ratio 672 x 180 / (600 x 170) = 1.19
  EXPECT_EQ(render_spp_for(8, shown, near), 8);
  // 0.1 photo px per panel px: 67 photo pixels long, refined by 3 (0.33 px) to reach 160.
  shown.px_per_panel_px = 0.1;
  const PhotoCrop fine = render_grid_for(shown);
  EXPECT_NEAR(fine.px_per_panel_px, 1.0 / 3.0, 1e-12);
  EXPECT_GE(std::max(fine.width, fine.height), kMinRenderSide);
  EXPECT_LE(fine.origin_px.x, shown.origin_px.x);
  EXPECT_GE(fine.origin_px.x + fine.width * fine.px_per_panel_px, shown.origin_px.x + 67.2 - 1e-9);
  // Never finer than the panel: 0.9 photo px per panel px gives the photo's grid.
  shown.px_per_panel_px = 0.9;
  EXPECT_EQ(render_grid_for(shown).px_per_panel_px, 1.0);
}

TEST(PhotoView, ARenderOnThePhotosGridIsShownAsThePhotoIs) {
  // A render traced on the photo's grid and shown on the panel equals the photo's
  // own crop of the same picture: both go through the same footprints.
  Image photo(256, 128, 3);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 256; ++x) photo.set_rgb(x, y, glm::vec3(float((x / 3 + y) % 2), float(x) / 256, float(y) / 128));
  PhotoCrop shown;
  shown.origin_px = {5.25, 3.5};
  shown.px_per_panel_px = 0.5;
  shown.width = 400, shown.height = 200;
  const PhotoCrop g = render_grid_for(shown);
  ASSERT_EQ(g.px_per_panel_px, 1.0);
  Image traced(g.width, g.height, 3);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) traced.set_rgb(x, y, photo.rgb(int(g.origin_px.x) + x, int(g.origin_px.y) + y));
  const Image a = show_on_panel(traced, g, shown), b = crop_photo(photo, shown);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  for (std::size_t i = 0; i < a.pixels.size(); ++i) ASSERT_NEAR(a.pixels[i], b.pixels[i], 1e-6f) << i;
  // The panel's own grid: shown as traced.
  shown.px_per_panel_px = 2;
  const Image same(shown.width, shown.height, 3, 0.25f);
  EXPECT_EQ(show_on_panel(same, render_grid_for(shown), shown).pixels, same.pixels);
}

namespace {
// A light card with a dark disc of radius r at (cx, cy), optionally with a card-coloured hole.
Image disc(int w, int h, double cx, double cy, double r, double hole = 0) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      img.set_rgb(x, y, d < r && d >= hole ? glm::vec3(0.3f, 0.1f, 0.1f) : glm::vec3(0.9f));
    }
  return img;
}
PanelRegions everywhere(int w, int h, int split_x) {
  PanelRegions r;
  r.width = w, r.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) r.side.push_back(x < split_x ? 1 : 2);
  return r;
}
}  // namespace

TEST(Fidelity, IouOfShiftedDiscsAndColourOfTheSameDisc) {
  const int w = 200, h = 120;
  const PanelRegions regions = everywhere(w, h, 100);
  const FidelitySettings settings;
  const MeasuredPanel photo = measure_panel(disc(w, h, 100, 60, 40), regions, settings);
  // The same disc: IoU 1, no colour difference, backdrop found.
  const RenderFidelity same = compare_panels(photo, measure_panel(disc(w, h, 100, 60, 40), regions, settings), regions);
  EXPECT_NEAR(same.feather.iou, 1.0, 1e-12);
  EXPECT_NEAR(same.feather.mean_colour_de2000, 0.0, 1e-6);
  EXPECT_NEAR(same.backdrop_de2000, 0.0, 1e-6);
  EXPECT_NEAR(photo.backdrop.x, 0.9f, 1e-5f);
  // Shifted by 20 px: two discs of radius 40 at distance 20 overlap by
  // 2 r^2 acos(d / 2r) - (d / 2) sqrt(4 r^2 - d^2); IoU = overlap / (2 pi r^2 - overlap).
  const RenderFidelity shifted =
      compare_panels(photo, measure_panel(disc(w, h, 120, 60, 40), regions, settings), regions);
  const double r = 40, d = 20, lens = 2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d);
  EXPECT_NEAR(shifted.feather.iou, lens / (2 * 3.14159265358979 * r * r - lens), 0.02);
  // The left half (the shifted disc leaves it) matches worse than the right.
  EXPECT_LT(shifted.left.iou, shifted.right.iou);
  // A lighter render: the colour difference grows, the silhouette stays.
  Image light = disc(w, h, 100, 60, 40);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (light.rgb(x, y).x < 0.5f) light.set_rgb(x, y, {0.4f, 0.15f, 0.15f});
  const RenderFidelity lighter = compare_panels(photo, measure_panel(light, regions, settings), regions);
  EXPECT_NEAR(lighter.feather.iou, 1.0, 1e-12);
  const double expect =
      ciede2000(linear_rgb_to_lab({0.3f, 0.1f, 0.1f}), linear_rgb_to_lab({0.4f, 0.15f, 0.15f}));
  EXPECT_NEAR(lighter.feather.mean_colour_de2000, expect, 0.1 * expect);  // the blurred edge pulls the means a little
}

TEST(Fidelity, SilhouettesHaveNoHolesButKeepGapsOpenToTheEdge) {
  const int w = 200, h = 120;
  const PanelRegions regions = everywhere(w, h, 100);
  // A ring: its card-coloured centre is a hole, so the silhouette is the full disc.
  const MeasuredPanel ring = measure_panel(disc(w, h, 100, 60, 40, 15), regions, {});
  const MeasuredPanel full = measure_panel(disc(w, h, 100, 60, 40), regions, {});
  EXPECT_NEAR(compare_panels(full, ring, regions).feather.iou, 1.0, 1e-12);
  // A slot cut from the disc to the panel's edge stays a gap.
  Image slot = disc(w, h, 100, 60, 40);
  for (int y = 55; y < 65; ++y)
    for (int x = 100; x < w; ++x) slot.set_rgb(x, y, glm::vec3(0.9f));
  EXPECT_LT(compare_panels(full, measure_panel(slot, regions, {}), regions).feather.iou, 0.97);
}

TEST(Fidelity, PatternAndEdgeMeasures) {
  // The luminance correlation sees the pattern: the same striped disc correlates 1,
  // a darker copy still 1 (the pattern, not the level), a plain disc barely. The
  // perimeter ratio sees the edge: 1 for the same disc, above 1.2 for the disc with a
  // saw-tooth rim of the same size (the staircase of square ribbon ends).
  const int w = 200, h = 120;
  const PanelRegions regions = everywhere(w, h, 100);
  const auto striped = [&](float scale) {
    Image img = disc(w, h, 100, 60, 40);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (img.rgb(x, y).x < 0.5f) img.set_rgb(x, y, ((x / 6) % 2 ? glm::vec3(0.3f, 0.1f, 0.1f) : glm::vec3(0.1f, 0.05f, 0.05f)) * scale);
    return img;
  };
  const MeasuredPanel photo = measure_panel(striped(1.0f), regions, {});
  const RenderFidelity same = compare_panels(photo, measure_panel(striped(1.0f), regions, {}), regions);
  EXPECT_NEAR(same.feather.luminance_correlation, 1.0, 1e-9);
  EXPECT_NEAR(same.perimeter_ratio, 1.0, 1e-12);
  EXPECT_NEAR(compare_panels(photo, measure_panel(striped(0.6f), regions, {}), regions).feather.luminance_correlation, 1.0, 1e-3);
  EXPECT_LT(std::abs(compare_panels(photo, measure_panel(disc(w, h, 100, 60, 40), regions, {}), regions).feather.luminance_correlation), 0.3);
  Image saw = disc(w, h, 100, 60, 40);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double d = std::hypot(x + 0.5 - 100, y + 0.5 - 60);
      if (d < 44 && d >= 36 && ((x / 4 + y / 4) % 2)) saw.set_rgb(x, y, d < 40 ? glm::vec3(0.9f) : glm::vec3(0.3f, 0.1f, 0.1f));
    }
  EXPECT_GT(compare_panels(measure_panel(disc(w, h, 100, 60, 40), regions, {}), measure_panel(saw, regions, {}), regions).perimeter_ratio, 1.2);
}

TEST(Fidelity, PanelsOfAnotherSizeAreRefused) {
  const PanelRegions regions = everywhere(50, 40, 25);
  EXPECT_THROW(measure_panel(Image(40, 40, 3), regions, {}), Error);
}

TEST(ClosedVane, EveryBarbOfAPhotoFeatherIsCoveredAndTheRibbonsOverlap) {
  // A feather analysed from a drawn photo, built as generate --layout builds it.
  synthetic::SyntheticFeather sf;
  sf.width = 450, sf.height = 350, sf.calamus = {125, 320}, sf.length = 280;
  sf.w_left = 30, sf.w_right = 48, sf.spacing = 6;
  const fs::path dir = fs::temp_directory_path() / ("plumage_closed_vane_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_image(dir / "photo.png", sf.draw());
  AnalyzeOptions ao;
  ao.mm_per_px = 0.2;
  const PhotoAnalysis a = analyze_photo(dir / "photo.png", ao);
  FeatherLayout layout = a.layout.feathers.front();
  layout.albedo.file.clear();  // geometry only
  const Feather f = layout_to_feather(layout, 1, dir, dir);
  fs::remove_all(dir);
  for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
    const SubstructureParams& p = f.substructure(side);
    // The ribbons reach over the gap between neighbouring barbs ...
    EXPECT_NEAR(p.ribbon_width, kBarbOverlap * barb_gap_mm(f, side), 1e-4) << to_string(side);
    EXPECT_GT(p.ribbon_width, barb_gap_mm(f, side));
    // ... and barbules cover every barb's ribbon (control polygon >= arc length), so
    // the coverage part of the albedo mapping (photo_albedo_to_fibre) is the identity.
    const BarbSubstructure sub(p, side);
    int barbs = 0;
    for (const Curve& c : f.curves) {
      if (c.kind != CurveKind::Barb || c.side != side) continue;
      double length = 0;
      for (std::size_t i = 1; i < c.points.size(); ++i) length += glm::length(c.points[i].p - c.points[i - 1].p);
      EXPECT_DOUBLE_EQ(sub.covered_fraction(length), 1.0);
      ++barbs;
    }
    EXPECT_GT(barbs, 10);
    // With 10 % fewer barbules the longest barb is no longer covered.
    SubstructureParams fewer = p;
    fewer.barbules_per_side = int(p.barbules_per_side / 1.12);
    double longest = 0;
    for (const Curve& c : f.curves)
      if (c.kind == CurveKind::Barb && c.side == side) {
        double length = 0;
        for (std::size_t i = 1; i < c.points.size(); ++i) length += glm::length(c.points[i].p - c.points[i - 1].p);
        longest = std::max(longest, length);
      }
    EXPECT_LT(BarbSubstructure(fewer, side).covered_fraction(longest), 1.0);
  }
}

// Issue 12's bounds on real photos, at a smaller panel and fewer samples than the
// defaults (the study at the defaults: docs/analysis.md, "Photo-to-feather study").
class PhotoFidelityBounds : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("plumage_photo_fidelity_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  nlohmann::json run(const fs::path& photo, const std::string& extra) {
    const auto r = test::plumage_cli("-q photo-to-feather " + photo.string() + " -o " + dir_.string() +
                                     " --size 336 --spp 4 --threads 2 " + extra);
    EXPECT_EQ(r.rc, 0) << r.output;
    return nlohmann::json::parse(read_file(dir_ / "summary.json")).at("fidelity");
  }
  // Both render panels: silhouette IoU >= 0.85, the feather's mean colour within
  // `colour_de` and the card within `card_de` (ΔE00) of the photo's.
  static void expect_bounds(const nlohmann::json& f, double colour_de, double card_de) {
    for (const char* panel : {"hair", "substructure"}) {
      EXPECT_GE(f.at(panel).at("feather").at("silhouette_iou").get<double>(), 0.85) << panel;
      EXPECT_LE(f.at(panel).at("feather").at("mean_colour_de2000").get<double>(), colour_de) << panel;
      EXPECT_LE(f.at(panel).at("backdrop_de2000").get<double>(), card_de) << panel;
    }
  }
  fs::path dir_;
};

TEST_F(PhotoFidelityBounds, PinkFeather) {
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "pink-contour-feather.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  // The calibration and the shading models, on the raw renders: the filter
  // (denoise.h) moves the panels' mean colour over the photo's mask by about 0.2
  // ΔE00 (it smooths the sparse fluff at the outline toward the card), which the
  // calibration's probes, read unfiltered, do not see; PinkFeatherDenoised holds
  // the filtered panels.
  const nlohmann::json f = run(photo, "--no-denoise");
  // Each panel's colour calibrated on its own render (docs/analysis.md, "Colour
  // calibrated by rendering"): within ΔE00 1.5 of the photo's mean (1.9 hair, 1.3
  // substructure with the card-response table alone, --calibrate 0).
  expect_bounds(f, 1.5, 2.0);
  for (const char* panel : {"hair", "substructure"}) {
    const auto& probes = f.at(panel).at("calibration").at("probes");
    ASSERT_FALSE(probes.empty()) << panel;
    EXPECT_LT(f.at(panel).at("feather").at("mean_colour_de2000").get<double>(),
              probes.at(0).at("mean_colour_de2000").get<double>()) << panel;
  }
  // With both means at the photo's, the pattern is what separates the shading
  // models: the substructure panel about as close to the photo, pixel by pixel, as
  // hair's (the paper's claim). At this setting (4 spp, calibration probes at 1 spp)
  // the probe the calibration keeps moves the substructure panel's pixel ΔE00 by
  // about 0.5 from seed to seed (3.20 and 3.69 at seeds 1 and 2 with the downy base
  // built as ribbons; 3.77 and 3.16 built as down barbs, hair 3.35-3.49), so the
  // bound allows that; the p2f study at the defaults states the comparison
  // (docs/analysis.md, "Photo-to-feather study").
  EXPECT_LE(f.at("substructure").at("feather").at("pixel_de2000").get<double>(),
            f.at("hair").at("feather").at("pixel_de2000").get<double>() + 0.5);
}

TEST_F(PhotoFidelityBounds, PinkFeatherDenoised) {
  // photo-to-feather's default: each render filtered by its own variance
  // (docs/rendering.md, "Denoising"). The panels keep the bounds (silhouette IoU >=
  // 0.85, colour within ΔE00 1.5, the card within 2), and both are closer to the
  // photo pixel by pixel than the raw renders of the same seed (at this setting
  // 3.37 / 3.77 raw, 2.94 / 3.33 filtered, hair / substructure).
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "pink-contour-feather.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  const nlohmann::json raw = run(photo, "--no-denoise");
  const nlohmann::json f = run(photo, "");
  expect_bounds(f, 1.5, 2.0);
  for (const char* panel : {"hair", "substructure"})
    EXPECT_LT(f.at(panel).at("feather").at("pixel_de2000").get<double>(),
              raw.at(panel).at("feather").at("pixel_de2000").get<double>()) << panel;
}

// Issue 33's bound on pale feathers: pixel ΔE00 <= 10 for both render panels.
void expect_pixel_de(const nlohmann::json& f, double bound) {
  for (const char* panel : {"hair", "substructure"})
    EXPECT_LE(f.at(panel).at("feather").at("pixel_de2000").get<double>(), bound) << panel;
}

TEST_F(PhotoFidelityBounds, SpoonbillSheetFeather) {
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "spoonbill-wing-sheet.png";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  // Pale pink on black: the fibres get a scattering medulla (docs/hair-bcsdf.md,
  // "Colours inverted through the renderer"); with clear fibres both panels came
  // out dark grey (pixel ΔE00 34-38 at the defaults). The card is the sheet's black,
  // not a neighbouring feather's colour.
  const nlohmann::json f = run(photo, "--feather 5 --grid-mm 20");
  expect_bounds(f, 8.0, 3.0);
  expect_pixel_de(f, 10.0);
  EXPECT_GT(f.at("hair").at("inversion").at("medulla").get<long>(), 0);
}

TEST_F(PhotoFidelityBounds, WhiteFeatherOnAGreyCard) {
  // Blue-jay F26, a white downy feather on the sheet's light grey card: its texture
  // holds it paler than the paper (layout albedo scale ~2) and its fibres get a
  // medulla; clamped at the paper's colour it rendered as the card (IoU 0.01).
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "blue-jay-feather-sheet.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  // Built as a plume of down barbs (docs/analysis.md, "Plumes: an open vane"), the
  // card shows between them; cut from its row of four plumes (docs/analysis.md,
  // "Pale parts") its outline is its own, but its shaft is traced leaning, so the
  // silhouettes overlap by 0.32 / 0.51 at the defaults: far from the card the
  // failure rendered (0.01).
  const nlohmann::json f = run(photo, "--feather 26");
  expect_pixel_de(f, 10.0);
  for (const char* panel : {"hair", "substructure"})
    EXPECT_GE(f.at(panel).at("feather").at("silhouette_iou").get<double>(), 0.2) << panel;
}

TEST_F(PhotoFidelityBounds, DarkFeatherOnAGreyCard) {
  // Robin feather 41: narrow dark vanes (1-3 mm) on a mid-grey card. With the card
  // four rachis radii under the barbs the dome lit it from the side under them and
  // the vane came out too light (IoU 0.80 / 0.84 at the defaults); with the card
  // under the vane (BackdropPlacement::Vane) and the correction fitted there, 0.88 /
  // 0.91 (at this setting 0.905 / 0.897, colour dE00 3.2 / 4.1, card 0.03).
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "european-robin-feather-sheet.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << photo << " not present";
  expect_bounds(run(photo, "--feather 41"), 8.0, 2.0);
}
