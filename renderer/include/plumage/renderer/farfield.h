#pragma once
// The far-field barb model (`--shading farfield`, docs/substructure.md "Far-field
// model"): a barb is a ribbon of width W in the vane, shaded by a table measured on
// explicit geometry (explicit_geometry.h) instead of by its rami and barbules.
//
// A virtual gonioreflectometer (farfield_fit.cpp) shoots parallel light at a patch of
// one explicit barb from every direction bin, follows each path through the ramus
// and barbules (round fibres, hair BCSDF) until it leaves, and records
//   T(d)         the fraction of a beam along d that crosses the ribbon untouched
//                (through the gaps between barbules), and
//   F[I][O]      the ribbon's BSDF, per unit ribbon area, from incident bin I to
//                outgoing bin O (RGB; 1/sr), read between bin centres by bilinear
//                interpolation in both directions,
// both in the barb frame (t along the barb, b' = distal side, n the vane normal), so
// the left vane uses the right vane's table with b mirrored.
//
// Directions are binned on Archimedes' equal-area map: x = d.t in nu equal steps of
// [-1, 1] (the longitudinal angle's sine, as for a fibre) and the azimuth
// phi = atan2(d.b', d.n) in nphi equal steps, so every bin has solid angle
// 4 pi / (nu nphi). The table is made reciprocal (F = F^T: the raw measurement is,
// up to its noise) and scaled where needed so that no row scatters more than
// 1 - T: the model never creates energy.
//
// In the renderer a ribbon hit is kept with probability 1 - T(d) (a stochastic
// decision in Embree's filters, so shadow rays see the same transmittance), and a
// kept hit scatters with F / (1 - T(wo)): the ribbon's light given that the ray did
// not pass through.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"
#include "plumage/renderer/hair_bcsdf.h"

namespace plumage {

// The equal-area direction bins of a far-field table.
struct FarfieldBins {
  int nu = 8, nphi = 16;  // nphi even (antipodes map bin to bin)
  int count() const { return nu * nphi; }
  float solid_angle() const;  // of one bin
  // The bin of a local direction (any length > 0); -1 for a non-finite or zero one.
  int bin(const glm::vec3& local) const;
  // A unit direction in bin `b` at (u.x, u.y) in [0,1)^2 of its (x, phi) extent:
  // uniform in u is uniform in solid angle.
  glm::vec3 direction(int b, const glm::vec2& u) const;
  // The bin holding the directions opposite to bin b's.
  int antipode(int b) const;
  // Bilinear weights of the four bins whose centres surround a direction in
  // (x, phi) (phi wraps; x is clamped at the poles); weights 0 for a bad direction.
  // `bin`, when given, receives bin(local) (-1 for a bad direction).
  struct Lerp {
    int b[4];
    float w[4];
  };
  Lerp lerp(const glm::vec3& local, int* bin = nullptr) const;
};

// What the table stands for: a vane's substructure, its barbule period along the
// barb (mm; the curve file's N is per barb, so the period is the vane's typical
// barb length / N), and the fibres' material. Its text is the cache key.
struct FarfieldGeometry {
  SubstructureParams params;
  float period = 0;  // barb length per barbule on one side (mm)
};

// How hard the gonioreflectometer works.
struct FarfieldFitSettings {
  FarfieldBins bins;
  int paths_per_bin = 8192;   // incident paths per direction bin
  int max_depth = 64;         // scattering events per path inside the patch
  std::uint32_t seed = 0x0ff1e1du;
  int threads = 0;            // 0 = all cores
  // The patch's ramus and barbules as round linear pieces within 2 % of their
  // radius of the B-splines (SceneOptions::explicit_polylines): about twice as fast
  // to intersect, the table within its noise of the B-spline patch's.
  bool polylines = true;
};

// What a fit found and how good it is (`--stats`, Farfield/...).
struct FarfieldReport {
  double seconds = 0;         // wall time of the fit (0 when loaded from the cache)
  std::int64_t paths = 0;     // incident paths traced
  std::int64_t rays = 0;      // rays traced in the patch
  double noise = 0;           // relative RMS standard error of the table's energy fractions (split-half)
  double asymmetry = 0;       // relative RMS of (P - P^T) / 2 before symmetrising, P the energy fractions
  double albedo_min = 0, albedo_max = 0;  // over bins: scattered fraction (max over RGB)
  double T_min = 0, T_max = 0;            // straight transmittance over bins
  double clamped = 0;         // largest relative scale-down the energy bound needed (0: none)
};

class FarfieldModel {
 public:
  FarfieldBins bins;
  std::vector<float> T;       // per bin: straight transmittance, T[b] = T[antipode(b)]
  std::vector<glm::vec3> F;   // [I * count + O]; empty for a transmittance-only model
  FarfieldReport report;

  bool has_bsdf() const { return !F.empty(); }
  // Straight transmittance along a local direction (either sense; interpolated); 1
  // for a bad one.
  float transmittance(const glm::vec3& local) const;
  // The terms of f_cos and sample that depend on wo alone (a shading point asks
  // for many wi with one wo).
  struct Outgoing {
    FarfieldBins::Lerp lo;
    float keep = 0;      // 1 - T(wo)
    float row_mass = 0;  // interpolation weight of wo's non-black rows
  };
  Outgoing outgoing(const glm::vec3& wo) const;
  // f(wi, wo) |wi.n| / (1 - T(wo)) for local unit directions (wo toward the viewer,
  // wi toward the light), and in *pdf (when not null) the density sample() gives wi.
  glm::vec3 f_cos(const glm::vec3& wo, const glm::vec3& wi, float* pdf) const { return f_cos(outgoing(wo), wi, pdf); }
  glm::vec3 f_cos(const Outgoing& o, const glm::vec3& wi, float* pdf) const;
  // f_cos's value within a few 1e-6 (the bins' azimuth from a float atan2), no pdf:
  // next-event estimation's weighing of the lights, where it chooses, not weighs.
  glm::vec3 f_cos_estimate(const Outgoing& o, const glm::vec3& wi) const;
  // Samples wi for wo: u.z picks one of the rows wo interpolates and then a bin of
  // that row in proportion to its energy, u.x and u.y a direction uniformly in the
  // bin. False when wo's rows are black. *weight = f_cos / pdf, pdf the mixture's.
  bool sample(const glm::vec3& wo, const glm::vec3& u, glm::vec3* wi, glm::vec3* weight, float* pdf) const {
    return sample(outgoing(wo), u, wi, weight, pdf);
  }
  bool sample(const Outgoing& o, const glm::vec3& u, glm::vec3* wi, glm::vec3* weight, float* pdf) const;
  // Scattered fraction for light from bin I's centre: sum_O F[I][O] H_O, H_O the
  // integral of bin O's interpolation weight times |d.n| over the sphere.
  glm::vec3 albedo(int I) const;
  // Mean |d.n| over bin b.
  float mean_cos(int b) const { return cbar_[std::size_t(b)]; }

  // Precomputes the bins' mean cosines and the sampling tables; call after filling T and F.
  void finish();

  // Binary cache file: throws plumage::Error naming what is wrong (truncated,
  // wrong magic or version, another key, bad checksum, non-finite or out-of-range data).
  std::string serialize(const std::string& key) const;
  static FarfieldModel deserialize(const std::string& bytes, const std::string& key);

 private:
  std::vector<float> cbar_;   // per bin: mean |d.n|
  std::vector<float> hat_;    // per bin: H_b, its interpolation weight times |d.n| integrated
  std::vector<float> cdf_;    // per O: (count + 1) cumulative weights over I
  void build_cdfs();
};

// The cache key: every parameter the table depends on, and the fit settings.
std::string farfield_key(const FarfieldGeometry& g, const HairParams* material, const FarfieldFitSettings& s);

// The virtual gonioreflectometer (farfield_fit.cpp): measures T, and F for `material`
// when given, on a straight explicit barb of the geometry's right vane.
FarfieldModel measure_farfield(const FarfieldGeometry& g, const HairParams* material, const FarfieldFitSettings& s);

// Where fitted tables are kept: $PLUMAGE_FARFIELD_CACHE when set (set but empty:
// no disk cache), else $XDG_CACHE_HOME/plumage/farfield, else
// ~/.cache/plumage/farfield; empty (no disk cache) when none of them is set.
std::filesystem::path farfield_cache_dir();

// The fit settings scenes and renders use: the defaults, with paths_per_bin from
// $PLUMAGE_FARFIELD_PATHS when set (2 to 10^7; otherwise plumage::Error naming it).
FarfieldFitSettings farfield_fit_settings();

// The model for a geometry (and material; nullptr: transmittance only): from this
// process's memory, else from the cache directory (a file named by the key's hash,
// whose stored key must match), else measured and written there atomically. A
// cache file that cannot be read or fails a check is reported in one line on
// stderr and refitted, never trusted. `cache_dir` empty: no disk cache.
std::shared_ptr<const FarfieldModel> farfield_model(const FarfieldGeometry& g, const HairParams* material,
                                                    const FarfieldFitSettings& s = farfield_fit_settings(),
                                                    const std::filesystem::path& cache_dir = farfield_cache_dir());

// Forgets the models held in memory (tests: the next call reads the disk cache).
void farfield_forget_memory();

}  // namespace plumage
