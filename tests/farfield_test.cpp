// The far-field barb model (farfield.h): its direction bins, the measured table's
// energy and reciprocity, the sampler against its pdf (chi-square), extreme
// directions, the disk cache (reuse, refit on a changed parameter, a damaged or
// stale file refused and refitted), and farfield mode through Embree and the
// integrator (pass-through rate, white furnace).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "plumage/common/atomic_file.h"
#include "plumage/common/constants.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/farfield.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/scene.h"
#include "chi_square.h"
#include "cli_run.h"
#include "furnace.h"
#include "one_barb.h"
#include "render_test_feather.h"

namespace plumage {
namespace {

// No test in this binary writes far-field tables to the user's cache: scenes in
// farfield mode (here, the stress and CLI tests) fit them in memory, with 1024
// paths per direction bin instead of 8192 (the noise, not the model, changes).
struct NoFarfieldDiskCache : ::testing::Environment {
  NoFarfieldDiskCache() {
    setenv("PLUMAGE_FARFIELD_CACHE", "", 1);
    setenv("PLUMAGE_FARFIELD_PATHS", "1024", 1);
  }
};
[[maybe_unused]] ::testing::Environment* const kNoDiskCache =
    ::testing::AddGlobalTestEnvironment(new NoFarfieldDiskCache);


// The presets' barb (rock dove: r_r 40 um, r_b 6 um, theta_b 45, phi_b 10, 30 % hooks, W 0.4 mm)
// with a barbule every 50 um.
FarfieldGeometry dove_geometry() {
  FarfieldGeometry g;
  g.params = test::substructure_params(100, 45, 0.04, 0.006, 0.4, 10, 0.3);
  g.period = 0.05f;
  return g;
}

FarfieldFitSettings small_fit(int paths = 3000) {
  FarfieldFitSettings s;
  s.bins = {6, 12};
  s.paths_per_bin = paths;
  return s;
}

HairParams material(float sigma_a) {
  HairParams hp;
  hp.sigma_a = glm::vec3(sigma_a, 2 * sigma_a, 3 * sigma_a);
  return hp;
}

// A fitted model shared by the tests that only read it (fitting takes a second).
const FarfieldModel& white_model() {
  static const FarfieldModel m = [] {
    const HairParams hp = material(0.0f);
    return measure_farfield(dove_geometry(), &hp, small_fit());
  }();
  return m;
}

const FarfieldModel& coloured_model() {
  static const FarfieldModel m = [] {
    const HairParams hp = material(0.3f);
    return measure_farfield(dove_geometry(), &hp, small_fit());
  }();
  return m;
}

glm::vec3 random_direction(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0, 1);
  const float z = 2 * u(rng) - 1, phi = 2 * float(kPi) * u(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

double stat(const std::string& name) { return stats_snapshot()[name]; }

using test::gamma_q;



}  // namespace

// --- bins ---------------------------------------------------------------------------

TEST(FarfieldBins, EqualAreaRoundTripAndAntipodes) {
  const FarfieldBins bins{6, 12};
  EXPECT_NEAR(bins.solid_angle() * bins.count(), 4 * kPi, 1e-5);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.01f, 0.99f);
  // Uniform (x, phi) in a bin is uniform on the sphere: the mean of z^2 is 1/3.
  double z2 = 0;
  int n = 0;
  for (int b = 0; b < bins.count(); ++b)
    for (int k = 0; k < 50; ++k) {
      const glm::vec3 d = bins.direction(b, {u(rng), u(rng)});
      ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
      ASSERT_EQ(bins.bin(d), b);
      ASSERT_EQ(bins.bin(-d), bins.antipode(b));
      z2 += d.z * d.z;
      ++n;
    }
  EXPECT_NEAR(z2 / n, 1.0 / 3, 0.01);
  EXPECT_EQ(bins.bin(glm::vec3(NAN, 0, 1)), -1);
  EXPECT_EQ(bins.bin(glm::vec3(0)), -1);
  // Interpolation weights sum to 1 and reproduce a bin centre exactly.
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 d = random_direction(rng);
    int b;
    const FarfieldBins::Lerp l = bins.lerp(d, &b);
    EXPECT_NEAR(l.w[0] + l.w[1] + l.w[2] + l.w[3], 1.0f, 1e-5f);
    ASSERT_EQ(b, bins.bin(d));
  }
  const FarfieldBins::Lerp c = bins.lerp(bins.direction(17, {0.5f, 0.5f}));
  float w17 = 0;
  for (int k = 0; k < 4; ++k) w17 += c.b[k] == 17 ? c.w[k] : 0.0f;
  EXPECT_NEAR(w17, 1.0f, 1e-4f);
}

// --- the measurement ------------------------------------------------------------------

// Without absorption every incident path is transmitted straight, or scattered and
// leaves: albedo + T = 1 up to the noise and the energy bound's clamp. With
// absorption less comes back, and never more than 1 - T.
TEST(FarfieldFit, EnergyConservedWithoutAbsorptionNeverCreated) {
  for (const FarfieldModel* m : {&white_model(), &coloured_model()}) {
    const bool white = m == &white_model();
    double worst = 0, lowest = 1;
    for (int b = 0; b < m->bins.count(); ++b) {
      const glm::vec3 a = m->albedo(b);
      const float amax = std::max({a.x, a.y, a.z});
      EXPECT_LE(amax, 1 - m->T[std::size_t(b)] + 1e-4f) << "bin " << b;
      worst = std::max(worst, double(amax + m->T[std::size_t(b)]));
      lowest = std::min(lowest, double(a.x + m->T[std::size_t(b)]));
      if (!white && a.x > 0) {
        EXPECT_LT(a.z, a.x) << "sigma_a is largest in blue";
      }
    }
    if (white) {
      EXPECT_GT(lowest, 0.85) << "the gonioreflectometer loses energy";
    }
    EXPECT_LE(worst, 1 + 1e-4);
  }
}

// Straight transmittance: at normal incidence about the uncovered share of the
// ribbon (1 - covered fraction: no lift or hooks), and nothing at grazing angles
// across the barb. The same both ways along a line.
TEST(FarfieldFit, TransmittanceMatchesCoverage) {
  FarfieldGeometry g = dove_geometry();
  g.params.azimuth_deg = 0;
  g.params.hooked_fraction = 0;
  FarfieldFitSettings s = small_fit(20000);
  s.bins = {9, 36};  // a narrow bin around the normal
  const FarfieldModel m = measure_farfield(g, nullptr, s);
  ASSERT_FALSE(m.has_bsdf());
  const BarbSubstructure vane(g.params, VaneSide::Right);
  const double length = 100 * g.period;
  const double open = 1 - vane.covered_fraction(length);
  EXPECT_NEAR(m.transmittance({0, 0, 1}), open, 0.06);
  EXPECT_NEAR(m.transmittance({0, 0, -1}), m.transmittance({0, 0, 1}), 1e-6);
  EXPECT_LT(m.transmittance({0, 1, 0.02f}), 0.05);
  // Thicker barbules let less through.
  g.params.barbule_radius *= 2;
  EXPECT_LT(measure_farfield(g, nullptr, s).transmittance({0, 0, 1}), open - 0.1);
}

// Reciprocity: the fitted table is symmetric, and the raw measurement nearly is:
// noise alone makes its asymmetry about noise / sqrt(2); the rest (about 0.16 RMS
// at the CLI's fit settings) comes from reading bin averages weighted by the
// outgoing cosine as values at the bins' centres, and from the hair BCSDF's own
// departures from reciprocity.
TEST(FarfieldFit, ReciprocalTableRawAsymmetryNearNoise) {
  const FarfieldModel& m = coloured_model();
  const int n = m.bins.count();
  for (int I = 0; I < n; ++I)
    for (int O = 0; O < n; ++O) ASSERT_EQ(m.F[std::size_t(I) * n + O], m.F[std::size_t(O) * n + I]);
  EXPECT_GT(m.report.noise, 0.0);
  EXPECT_GT(m.report.asymmetry, 0.5 * m.report.noise) << "the split halves cannot be that alike";
  EXPECT_LT(m.report.asymmetry, 0.25) << "noise " << m.report.noise;
  // The model's own reciprocity, through interpolation: f(wi, wo) = f(wo, wi).
  std::mt19937 rng(3);
  for (int k = 0; k < 200; ++k) {
    const glm::vec3 a = random_direction(rng), b = random_direction(rng);
    if (std::fabs(a.z) < 1e-3f || std::fabs(b.z) < 1e-3f) continue;
    float pa, pb;
    const glm::vec3 fab = m.f_cos(a, b, &pa) * (1 - m.transmittance(a)) / std::fabs(b.z);
    const glm::vec3 fba = m.f_cos(b, a, &pb) * (1 - m.transmittance(b)) / std::fabs(a.z);
    EXPECT_NEAR(fab.x, fba.x, 1e-4f * (1 + fab.x));
  }
}

// White furnace at depth 1: for any wo, the kept hit's albedo, the integral of
// f_cos over wi (estimated by sampling the model), is at most 1; for sigma_a = 0
// it is close to 1 where the ribbon is not mostly see-through.
TEST(FarfieldFit, DepthOneFurnace) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  for (const FarfieldModel* m : {&white_model(), &coloured_model()})
    for (int k = 0; k < 40; ++k) {
      const glm::vec3 wo = random_direction(rng);
      double sum = 0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {
        glm::vec3 wi, w;
        float pdf;
        if (m->sample(wo, {u(rng), u(rng), u(rng)}, &wi, &w, &pdf)) sum += std::max({w.x, w.y, w.z});
      }
      EXPECT_LE(sum / n, 1.02) << "wo " << wo.x << "," << wo.y << "," << wo.z;
    }
}

// Pearson's chi-square test of the sampler against its pdf, integrated over
// 4 x 4 sub-cells of every bin (the pdf is constant within a bin), cells expecting
// fewer than 5 samples pooled. Family-wise significance 1 % over the cases.
TEST(FarfieldFit, SamplingMatchesPdfChiSquare) {
  const FarfieldModel& m = coloured_model();
  const FarfieldBins& bins = m.bins;
  const int sub = 4, nsamples = 200000;
  const glm::vec3 wos[] = {{0, 0, 1}, {0.3f, -0.5f, 0.81f}, {-0.9f, 0.1f, -0.42f}, {0.05f, 0.99f, 0.1f}};
  const double alpha = 1 - std::pow(0.99, 1.0 / 4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  for (glm::vec3 wo : wos) {
    wo = glm::normalize(wo);
    const int cells = bins.count() * sub * sub;
    std::vector<double> expected(std::size_t(cells), 0.0), observed(std::size_t(cells), 0.0);
    for (int b = 0; b < bins.count(); ++b) {
      float pdf;
      m.f_cos(wo, bins.direction(b, {0.5f, 0.5f}), &pdf);
      for (int c = 0; c < sub * sub; ++c)
        expected[std::size_t(b * sub * sub + c)] = pdf * bins.solid_angle() / (sub * sub) * nsamples;
    }
    for (int k = 0; k < nsamples; ++k) {
      glm::vec3 wi, w;
      float pdf;
      ASSERT_TRUE(m.sample(wo, {u(rng), u(rng), u(rng)}, &wi, &w, &pdf));
      float pdf2;
      const glm::vec3 fc = m.f_cos(wo, wi, &pdf2);
      ASSERT_NEAR(pdf, pdf2, 1e-5f * pdf);
      ASSERT_NEAR(w.x, fc.x / pdf, 1e-4f * (1 + w.x));
      const int b = bins.bin(wi);
      const double x = (double(wi.x) + 1) / 2 * bins.nu - b / bins.nphi;
      const double phi = (std::atan2(double(wi.y), double(wi.z)) + kPi) / (2 * kPi) * bins.nphi - b % bins.nphi;
      const int cx = std::clamp(int(x * sub), 0, sub - 1), cp = std::clamp(int(phi * sub), 0, sub - 1);
      observed[std::size_t(b * sub * sub + cx * sub + cp)] += 1;
    }
    const test::ChiSquare cs = test::pearson_pooled(expected, observed);
    EXPECT_NEAR(cs.total_expected / nsamples, 1.0, 1e-3) << "the pdf does not integrate to 1";
    EXPECT_GT(cs.pvalue, alpha) << "chi2 " << cs.chi2 << " dof " << cs.dof;
  }
}

// The test above can fail: samples drawn from a different model's rows are rejected.
TEST(FarfieldFit, ChiSquareRejectsAnotherModel) {
  const FarfieldModel& m = coloured_model();
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, -0.5f, 0.81f)), other(0, 0, -1);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0, 1);
  const int nsamples = 50000;
  std::vector<double> observed(std::size_t(m.bins.count()), 0.0);
  for (int k = 0; k < nsamples; ++k) {
    glm::vec3 wi, w;
    float pdf;
    if (m.sample(other, {u(rng), u(rng), u(rng)}, &wi, &w, &pdf)) observed[std::size_t(m.bins.bin(wi))] += 1;
  }
  double chi2 = 0;
  int dof = -1;
  for (int b = 0; b < m.bins.count(); ++b) {
    float pdf;
    m.f_cos(wo, m.bins.direction(b, {0.5f, 0.5f}), &pdf);
    const double e = pdf * m.bins.solid_angle() * nsamples;
    if (e < 5) continue;
    chi2 += (observed[std::size_t(b)] - e) * (observed[std::size_t(b)] - e) / e;
    ++dof;
  }
  EXPECT_LT(gamma_q(0.5 * dof, 0.5 * chi2), 1e-6);
}

// Extreme directions: exactly grazing, along the barb, non-finite: finite
// non-negative values, no crash, no sample from a bad direction.
TEST(FarfieldFit, ExtremeDirectionsStayFinite) {
  const FarfieldModel& m = white_model();
  const glm::vec3 dirs[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0.6f, 0.8f, 0}, {0, 0, 1e-9f},
                            {1, 1e-7f, 0}, {0, 0, -1}};
  for (const glm::vec3& wo : dirs)
    for (const glm::vec3& wi : dirs) {
      float pdf;
      const glm::vec3 f = m.f_cos(wo, wi, &pdf);
      EXPECT_TRUE(std::isfinite(f.x) && f.x >= 0 && std::isfinite(pdf) && pdf >= 0);
      glm::vec3 s, w;
      if (m.sample(wo, {0.999999f, 0.999999f, 0.999999f}, &s, &w, &pdf)) {
        EXPECT_TRUE(std::isfinite(w.x) && w.x >= 0 && pdf > 0);
      }
      EXPECT_GE(m.transmittance(wo), 0.0f);
      EXPECT_LE(m.transmittance(wo), 1.0f);
    }
  float pdf;
  EXPECT_EQ(m.f_cos(glm::vec3(NAN, 0, 1), glm::vec3(0, 0, 1), &pdf), glm::vec3(0));
  glm::vec3 s, w;
  EXPECT_FALSE(m.sample(glm::vec3(NAN), glm::vec3(0.5f), &s, &w, &pdf));
  EXPECT_EQ(m.transmittance({0, 0, 0}), 1.0f);
}

// The paths per bin come from PLUMAGE_FARFIELD_PATHS; a bad value is refused, naming it.
TEST(FarfieldFit, PathsFromTheEnvironment) {
  EXPECT_EQ(farfield_fit_settings().paths_per_bin, 1024);  // the test environment's
  for (const char* bad : {"0", "1", "abc", "12x", "-5", "99999999999"}) {
    setenv("PLUMAGE_FARFIELD_PATHS", bad, 1);
    try {
      farfield_fit_settings();
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("PLUMAGE_FARFIELD_PATHS"), std::string::npos) << e.what();
    }
  }
  setenv("PLUMAGE_FARFIELD_PATHS", "1024", 1);
}

// --- the cache ------------------------------------------------------------------------

class FarfieldCache : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("plumage_farfield_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    std::filesystem::remove_all(dir_);
    farfield_forget_memory();
  }
  void TearDown() override {
    std::filesystem::remove_all(dir_);
    farfield_forget_memory();
  }
  std::vector<std::filesystem::path> files() const {
    std::vector<std::filesystem::path> out;
    if (std::filesystem::exists(dir_))
      for (const auto& e : std::filesystem::directory_iterator(dir_)) out.push_back(e.path());
    return out;
  }
  std::filesystem::path dir_;
};

constexpr const char* kFits = "Farfield/Tables fitted (gonioreflectometer runs)";
constexpr const char* kLoaded = "Farfield/Tables read from the disk cache";
constexpr const char* kRefused = "Farfield/Cache files refused and refitted";

TEST_F(FarfieldCache, SecondUseReadsTheFileChangedParameterRefits) {
  const HairParams hp = material(0.2f);
  const FarfieldFitSettings s = small_fit(300);
  const double fits0 = stat(kFits), loaded0 = stat(kLoaded);
  const auto a = farfield_model(dove_geometry(), &hp, s, dir_);
  EXPECT_EQ(stat(kFits), fits0 + 1);
  ASSERT_EQ(files().size(), 1u);
  EXPECT_EQ(farfield_model(dove_geometry(), &hp, s, dir_), a) << "the same process keeps it in memory";
  farfield_forget_memory();
  const auto b = farfield_model(dove_geometry(), &hp, s, dir_);
  EXPECT_EQ(stat(kFits), fits0 + 1) << "a second use must not refit";
  EXPECT_EQ(stat(kLoaded), loaded0 + 1);
  EXPECT_EQ(b->F, a->F);
  EXPECT_EQ(b->T, a->T);
  EXPECT_EQ(b->report.noise, a->report.noise);
  // Any parameter changed: another key, another fit.
  FarfieldGeometry g = dove_geometry();
  g.params.barbule_radius = 0.007f;
  farfield_model(g, &hp, s, dir_);
  EXPECT_EQ(stat(kFits), fits0 + 2);
  HairParams hp2 = hp;
  hp2.beta_m = 0.31f;
  farfield_model(dove_geometry(), &hp2, s, dir_);
  EXPECT_EQ(stat(kFits), fits0 + 3);
  EXPECT_EQ(files().size(), 3u);
}

TEST_F(FarfieldCache, DamagedOrStaleFileIsRefusedAndRefitted) {
  const HairParams hp = material(0.2f);
  const FarfieldFitSettings s = small_fit(300);
  const auto good = farfield_model(dove_geometry(), &hp, s, dir_);
  ASSERT_EQ(files().size(), 1u);
  const std::filesystem::path file = files()[0];
  const std::string bytes = read_file(file);
  auto damaged = [&](const std::string& contents, const char* why) {
    write_file_atomic(file, contents);
    farfield_forget_memory();
    const double fits0 = stat(kFits), refused0 = stat(kRefused);
    testing::internal::CaptureStderr();
    std::shared_ptr<const FarfieldModel> m;
    EXPECT_NO_THROW(m = farfield_model(dove_geometry(), &hp, s, dir_)) << why;
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(stat(kFits), fits0 + 1) << why;
    EXPECT_EQ(stat(kRefused), refused0 + 1) << why;
    EXPECT_NE(err.find("refitted and written over"), std::string::npos) << why << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << why << ": one line: " << err;
    ASSERT_TRUE(m);
    EXPECT_EQ(m->F, good->F) << why << ": the refit is deterministic";
    // ... and the file was rewritten: the next process reads it.
    farfield_forget_memory();
    const double fits1 = stat(kFits);
    farfield_model(dove_geometry(), &hp, s, dir_);
    EXPECT_EQ(stat(kFits), fits1) << why;
  };
  damaged("", "empty");
  damaged(bytes.substr(0, bytes.size() / 2), "truncated");
  std::string flipped = bytes;
  flipped[flipped.size() / 2] ^= 0x40;
  damaged(flipped, "one bit flipped");
  damaged("garbage that is not a table at all", "garbage");
  // Stale: a valid table fitted for other parameters under this key's file name.
  HairParams other = hp;
  other.eta = 1.4f;
  const std::string stale = measure_farfield(dove_geometry(), &other, s).serialize(farfield_key(dove_geometry(), &other, s));
  damaged(stale, "stale");
  // The deserialiser names what is wrong.
  try {
    FarfieldModel::deserialize(stale, farfield_key(dove_geometry(), &hp, s));
    ADD_FAILURE() << "a stale table was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("stale"), std::string::npos) << e.what();
  }
}

// --- through Embree and the integrator ------------------------------------------------


// Rays straight down onto a far-field ribbon are let through at the table's T
// for that direction (and the same ray is decided the same way every time).
TEST(FarfieldScene, PassThroughAtTheTablesRate) {
  const Feather f = test::one_barb(test::substructure_params(100, 45, 0.04, 0.006, 0.4, 10, 0.3));
  SceneOptions so;
  so.mode = ShadingMode::Farfield;
  const Scene scene(f, so);
  ASSERT_EQ(scene.farfield_geometries(VaneSide::Right).size(), 1u) << "one barb, one class";
  EXPECT_TRUE(scene.farfield_geometries(VaneSide::Left).empty());
  const FarfieldGeometry& g = scene.farfield_geometries(VaneSide::Right)[0];
  EXPECT_GT(g.period, 0.0f);
  EXPECT_EQ(g.params.ribbon_width, 0.4f);
  const float T = farfield_model(g, nullptr)->transmittance({0, 0, -1});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(-1.5, 1.5), uw(-0.19, 0.19);
  int hits = 0, same = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const Ray r = test::down_at(ux(rng), uw(rng));
    SurfaceHit h1, h2;
    const bool a = scene.intersect(r, h1), b = scene.intersect(r, h2);
    hits += a;
    same += a == b;
    EXPECT_EQ(scene.occluded(r), a);
  }
  EXPECT_EQ(same, n);
  const double sigma = std::sqrt(T * (1 - T) / n);
  EXPECT_NEAR(double(n - hits) / n, T, 5 * sigma + 1e-3);
}

// White furnace at full depth: with sigma_a = 0 under a white environment a
// far-field feather passes on at most what it receives.
TEST(FarfieldScene, FurnaceNoMoreEnergyOutThanIn) {
  Feather f = test::make_test_feather(12.0f, 0.4f, 0.05f);
  f.left = f.right = test::substructure_params(30, 40, 0.04, 0.012, 0.3, 10, 0.3);
  SceneOptions so;
  so.mode = ShadingMode::Farfield;
  test::expect_furnace(Scene(f, so), 0.85);
}

// The user's path: `plumage render --shading farfield --stats` fits and caches the
// tables, a second run reads them, and damaged files are reported one line each
// and refitted; a bad substructure parameter fails before anything is fitted.
TEST(FarfieldCli, RenderFitsThenReadsThenRefitsDamagedFiles) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("plumage_farfield_cli_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "cache");
  Feather f = test::make_test_feather(12.0f, 1.0f);
  f.left = f.right = test::substructure_params(20, 45, 0.04, 0.008, 0.4, 10, 0.3);
  write_fcurves(dir / "f.fcurves", f);
  setenv("PLUMAGE_FARFIELD_CACHE", (dir / "cache").c_str(), 1);
  const std::string cmd = "-q --stats render '" + (dir / "f.fcurves").string() +
                          "' --shading farfield --spp 1 --resolution 16x16 -o '" + (dir / "a.png").string() + "'";
  auto count = [](const std::string& err, const std::string& name) {
    std::smatch m;
    if (!std::regex_search(err, m, std::regex(name + R"( +([0-9]+))"))) return -1;
    return std::stoi(m[1]);
  };
  const auto first = test::plumage_cli_streams(cmd);
  ASSERT_EQ(first.rc, 0) << first.err;
  const int fitted = count(first.err, "Tables fitted \\(gonioreflectometer runs\\)");
  EXPECT_GE(fitted, 2) << "a transmittance and a BSDF table at least: " << first.err;
  EXPECT_EQ(count(first.err, "Tables read from the disk cache"), 0);
  EXPECT_NE(first.err.find("Fit: noise"), std::string::npos) << first.err;
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir / "cache")) files += e.is_regular_file();
  EXPECT_EQ(int(files), fitted);

  const auto second = test::plumage_cli_streams(cmd);
  ASSERT_EQ(second.rc, 0) << second.err;
  EXPECT_EQ(count(second.err, "Tables fitted \\(gonioreflectometer runs\\)"), 0) << second.err;
  EXPECT_EQ(count(second.err, "Tables read from the disk cache"), fitted);

  for (const auto& e : std::filesystem::directory_iterator(dir / "cache")) write_file_atomic(e.path(), "garbage");
  const auto third = test::plumage_cli_streams(cmd);
  ASSERT_EQ(third.rc, 0) << third.err;
  EXPECT_EQ(count(third.err, "Tables fitted \\(gonioreflectometer runs\\)"), fitted);
  EXPECT_EQ(count(third.err, "Cache files refused and refitted"), fitted);
  int warnings = 0;
  std::istringstream lines(third.err);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("plumage: warning: far-field cache ", 0) == 0) {
      ++warnings;
      EXPECT_NE(line.find("refitted and written over"), std::string::npos) << line;
      const std::string cache = (dir / "cache").string();
      EXPECT_EQ(line.find(cache), line.rfind(cache)) << "the file is named twice: " << line;
    }
  EXPECT_EQ(warnings, fitted) << third.err;

  // A cache folder that cannot be made: one warning line for the run, however many tables.
  write_file_atomic(dir / "a-file", "x");
  setenv("PLUMAGE_FARFIELD_CACHE", (dir / "a-file" / "cache").c_str(), 1);
  const auto unwritable = test::plumage_cli_streams(cmd);
  ASSERT_EQ(unwritable.rc, 0) << unwritable.err;
  int folder_lines = 0;
  std::istringstream unwritable_lines(unwritable.err);
  for (std::string line; std::getline(unwritable_lines, line);)
    if (line.find("far-field cache") != std::string::npos) {
      ++folder_lines;
      EXPECT_NE(line.find("cannot be written"), std::string::npos) << line;
      EXPECT_NE(line.find("$PLUMAGE_FARFIELD_CACHE"), std::string::npos) << line;
    }
  EXPECT_EQ(folder_lines, 1) << unwritable.err;
  setenv("PLUMAGE_FARFIELD_CACHE", (dir / "cache").c_str(), 1);

  const auto bad = test::plumage_cli_streams("render '" + (dir / "f.fcurves").string() +
                                             "' --shading farfield --barbule-elevation 0.2 -o '" +
                                             (dir / "bad.png").string() + "'");
  EXPECT_NE(bad.rc, 0);
  EXPECT_NE(bad.err.find("--barbule-elevation"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.png"));
  setenv("PLUMAGE_FARFIELD_CACHE", "", 1);
  std::filesystem::remove_all(dir);
}

// The fit's patch as polylines (FarfieldFitSettings::polylines, the default) stands
// for the B-spline patch: with the same sample streams, the transmittance agrees
// within the binomial noise of its paths and the table within the two fits' own
// split-half noise. The same comparison tells a patch with barbules 1.5x as thick.
TEST(FarfieldFit, PolylinePatchMatchesTheBSplinePatch) {
  const HairParams hp = material(0.3f);
  FarfieldFitSettings s = small_fit(4096);
  s.polylines = false;
  const FarfieldModel spline = measure_farfield(dove_geometry(), &hp, s);
  s.polylines = true;
  const FarfieldModel poly = measure_farfield(dove_geometry(), &hp, s);
  FarfieldGeometry thick_g = dove_geometry();
  thick_g.params.barbule_radius *= 1.5f;
  const FarfieldModel thick = measure_farfield(thick_g, &hp, s);
  const auto differences = [&](const FarfieldModel& a, const FarfieldModel& b) {
    double t_worst = 0, d2 = 0, f2 = 0;
    for (int i = 0; i < a.bins.count(); ++i) {
      const double T = 0.5 * (a.T[std::size_t(i)] + b.T[std::size_t(i)]);
      const double sigma = std::sqrt(std::max(T * (1 - T), 1.0 / s.paths_per_bin) / s.paths_per_bin);
      t_worst = std::max(t_worst, std::fabs(double(a.T[std::size_t(i)] - b.T[std::size_t(i)])) / sigma);
    }
    for (std::size_t k = 0; k < a.F.size(); ++k) {
      const glm::dvec3 d = glm::dvec3(a.F[k] - b.F[k]), f = glm::dvec3(a.F[k] + b.F[k]) * 0.5;
      d2 += glm::dot(d, d);
      f2 += glm::dot(f, f);
    }
    return std::pair{t_worst, std::sqrt(d2 / f2)};
  };
  const double noise = std::max(spline.report.noise, poly.report.noise);
  const auto [t_same, f_same] = differences(spline, poly);
  EXPECT_LT(t_same, 4.0) << "transmittance, in binomial standard deviations";
  EXPECT_LT(f_same, 1.5 * noise) << "the table's noise is " << noise;
  const auto [t_thick, f_thick] = differences(poly, thick);
  EXPECT_GT(t_thick, 4.0);
  EXPECT_GT(f_thick, 1.5 * noise);
  std::printf("  polylines vs B-splines: T %.2f sigma, F %.4f (noise %.4f); thicker barbules: T %.1f sigma, F %.4f\n",
              t_same, f_same, noise, t_thick, f_thick);
}

// f_cos reads row O of the symmetric table where the model is defined by column O
// (F[I][O]): the same numbers, so the same value to the bit. The estimate that
// weighs the lights for next-event estimation (its azimuth from a float atan2)
// follows f_cos within 1e-4 of the table's largest entry. A cache file whose table is not
// symmetric is refused.
TEST(Farfield, RowReadsEqualTheTableAndTheEstimateFollowsFCos) {
  const FarfieldModel& m = coloured_model();
  const std::size_t n = std::size_t(m.bins.count());
  float largest = 0;
  for (const glm::vec3& v : m.F) largest = std::max({largest, v.x, v.y, v.z});
  std::mt19937 rng(23);
  int compared = 0;
  for (int t = 0; t < 4000; ++t) {
    const glm::vec3 wo = random_direction(rng), wi = random_direction(rng);
    const FarfieldModel::Outgoing o = m.outgoing(wo);
    const glm::vec3 f = m.f_cos(o, wi, nullptr);
    int I;
    const FarfieldBins::Lerp li = m.bins.lerp(wi, &I);
    glm::vec3 want(0);
    if (I >= 0 && o.keep > 0) {
      for (int k = 0; k < 4; ++k) {
        if (!(o.lo.w[k] > 0)) continue;
        glm::vec3 fk(0);
        for (int j = 0; j < 4; ++j) fk += li.w[j] * m.F[std::size_t(li.b[j]) * n + std::size_t(o.lo.b[k])];
        want += o.lo.w[k] * fk;
      }
      want *= std::fabs(wi.z) / std::sqrt(glm::dot(wi, wi)) / o.keep;
    }
    ASSERT_EQ(f, want) << t;
    // The azimuth's error (1e-5 rad) moves the interpolation weights by about
    // 1e-5 nphi / 2 pi: a share of the table's scale, not of f.
    const glm::vec3 e = m.f_cos_estimate(o, wi);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(e[c], f[c], 1e-4f * largest / std::max(o.keep, 1e-3f)) << t;
    compared += f.x > 0;
  }
  EXPECT_GT(compared, 1000);

  FarfieldModel lopsided = coloured_model();
  lopsided.F[1] *= 1.5f;  // F[0][1] no longer F[1][0]
  const std::string bytes = lopsided.serialize("key");
  try {
    FarfieldModel::deserialize(bytes, "key");
    ADD_FAILURE() << "an asymmetric table was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not symmetric"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(FarfieldModel::deserialize(coloured_model().serialize("key"), "key"));
}

}  // namespace plumage
