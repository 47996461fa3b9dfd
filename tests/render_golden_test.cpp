// The rock-dove preset feather (generator, seed 1) under the 25-LED dome compared
// with a stored reference image (data/golden/render_rock_dove_dome25.exr) with a tolerance, the way the Embree
// tutorials guard their renderers. After an intended change to the renderer or
// the BCSDF, regenerate the reference with
//   PLUMAGE_UPDATE_GOLDEN=1 build/plumage_tests --gtest_filter='RenderGolden.*'
// and look at it before committing. A change to the preset or the generator also
// changes the picture and needs the same.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "plumage/common/image.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/render.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

Image render_under_dome(const std::string& led_selection, std::uint64_t seed = 1) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f)};
  static const Feather feather = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  const Scene scene(feather, so);
  const DomeRig rig = read_dome_rig(fs::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  const Bounds3f& fb = scene.feather_bounds();
  LightSet lights;
  for (const SphereLight& l : dome_lights(rig, parse_light_selection(led_selection, 25),
                                          {fb.centre().x, fb.centre().y, fb.lo.z}))
    lights.add(l);
  const FibreMaterial material(HairParams{}, AlbedoMap(feather.albedo, "."));
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{8, 3});
  const Camera camera(CameraSpec{}, 40, 64, fb);
  RenderSettings rs;
  rs.spp = 64;
  rs.seed = seed;
  rs.progress = false;
  return render(camera, integrator, rs).developed(0);
}

// 4x4 box average: Monte Carlo noise (which differs between machines once a
// single path diverges) averages out, changes in the lighting do not.
Image box4(const Image& img) {
  Image out(img.width / 4, img.height / 4, img.channels);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < img.channels; ++c) {
        float s = 0;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) s += img.at(4 * x + i, 4 * y + j)[c];
        out.at(x, y)[c] = s / 16;
      }
  return out;
}

// On the box-averaged images: mean absolute difference relative to the
// reference's mean, and PSNR (dB) with the reference's maximum as peak.
struct Diff {
  double rel_mae, psnr;
};
Diff compare(const Image& full_img, const Image& full_ref) {
  const Image img = box4(full_img), ref = box4(full_ref);
  double abs_sum = 0, sq_sum = 0, ref_sum = 0, peak = 0;
  for (std::size_t i = 0; i < ref.pixels.size(); ++i) {
    const double d = double(img.pixels[i]) - ref.pixels[i];
    abs_sum += std::fabs(d);
    sq_sum += d * d;
    ref_sum += ref.pixels[i];
    peak = std::fmax(peak, ref.pixels[i]);
  }
  const double n = double(ref.pixels.size());
  return {abs_sum / std::fmax(ref_sum, 1e-12), 10 * std::log10(peak * peak / std::fmax(sq_sum / n, 1e-30))};
}

const fs::path kGolden = fs::path(PLUMAGE_DATA_DIR) / "golden/render_rock_dove_dome25.exr";
constexpr double kMaxRelMae = 0.03;
constexpr double kMinPsnr = 28.0;

}  // namespace

TEST(RenderGolden, FeatherUnderDome25MatchesReference) {
  const Image img = render_under_dome("all");
  if (std::getenv("PLUMAGE_UPDATE_GOLDEN")) {
    write_image(kGolden, img);
    GTEST_SKIP() << "wrote " << kGolden;
  }
  const Image ref = read_image(kGolden);
  ASSERT_EQ(ref.width, img.width);
  ASSERT_EQ(ref.height, img.height);
  ASSERT_EQ(ref.channels, img.channels);
  const Diff d = compare(img, ref);
  EXPECT_LT(d.rel_mae, kMaxRelMae);
  EXPECT_GT(d.psnr, kMinPsnr);
  // The tolerance admits Monte Carlo noise: another seed passes too.
  const Diff reseeded = compare(render_under_dome("all", 2), ref);
  EXPECT_LT(reseeded.rel_mae, kMaxRelMae);
  EXPECT_GT(reseeded.psnr, kMinPsnr) << reseeded.rel_mae;
}

TEST(RenderGolden, ComparisonCatchesAChangedLightSubset) {
  if (std::getenv("PLUMAGE_UPDATE_GOLDEN")) GTEST_SKIP();
  const Image ref = read_image(kGolden);
  // Switching off the 60-degree ring (LEDs 2-9) must show.
  const Diff no_ring = compare(render_under_dome("1,10-25"), ref);
  EXPECT_TRUE(no_ring.rel_mae > kMaxRelMae && no_ring.psnr < kMinPsnr)
      << "rel MAE " << no_ring.rel_mae << " PSNR " << no_ring.psnr;
  const Diff single = compare(render_under_dome("1"), ref);
  EXPECT_GT(single.rel_mae, kMaxRelMae) << single.psnr;
  EXPECT_LT(single.psnr, kMinPsnr);
}
