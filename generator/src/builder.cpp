#include "plumage/generator/builder.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/constants.h"
#include "plumage/common/stats.h"
#include "plumage/generator/random.h"
#include "shaft.h"

namespace plumage {

namespace {

// A down barb's barbules shorten toward its tip: over the last kDownTipTaper of the
// barb its radius falls (smoothstep) by kDownTipNarrowing of afterfeather.radius, so
// the fluff's edge is a soft line, not a row of blunt tube ends (kBarbTipTaper does
// the same for a ribbon).
constexpr double kDownTipTaper = 0.2;
constexpr double kDownTipNarrowing = 0.75;
constexpr int kSubsteps = 4;           // RK2 steps per barb station
constexpr int kCageFitIterations = 3;  // see fit_cage_to_targets

StatCounter barbs_traced("Generator/Barbs traced");
StatCounter surface_samples("Generator/Vane limit-surface evaluations");

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// The vane's half-width (mm) at position x, kept off zero so the surface never
// collapses to a line (its normal would be undefined at a pointed tip).
double half_width(const VaneParams& v, double x) {
  return std::max(v.width(x), 1e-3 * v.width.max_value());
}

// Limit positions of a regular grid with sharp boundaries: the cubic B-spline
// limit mask (1,4,1)/6 along each direction, the identity across a boundary.
std::vector<glm::dvec3> limit_points(const std::vector<glm::dvec3>& P, int nc, int nr) {
  auto along = [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) { return (a + 4.0 * b + c) / 6.0; };
  std::vector<glm::dvec3> tmp(P.size()), out(P.size());
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nr; ++j)
      tmp[i * nr + j] = (i == 0 || i == nc - 1) ? P[i * nr + j]
                                                : along(P[(i - 1) * nr + j], P[i * nr + j], P[(i + 1) * nr + j]);
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nr; ++j)
      out[i * nr + j] = (j == 0 || j == nr - 1) ? tmp[i * nr + j]
                                                : along(tmp[i * nr + j - 1], tmp[i * nr + j], tmp[i * nr + j + 1]);
  return out;
}

// Control points whose limit surface passes (nearly) through the targets: the
// limit mask shrinks a sampled surface by O(h^2 curvature); a few Jacobi steps
// P += F - limit(P) undo most of it (the mask's eigenvalues lie in [1/9, 1]).
std::vector<glm::dvec3> fit_cage_to_targets(const std::vector<glm::dvec3>& F, int nc, int nr) {
  std::vector<glm::dvec3> P = F;
  for (int it = 0; it < kCageFitIterations; ++it) {
    const auto L = limit_points(P, nc, nr);
    for (std::size_t k = 0; k < P.size(); ++k) P[k] += F[k] - L[k];
  }
  return P;
}

struct VaneBuilder {
  const FeatherParams& p;
  const Shaft& shaft;
  VaneSide side;
  double s0, lv;  // vane start (arc length) and vane length along the shaft

  const VaneParams& vane() const { return p.vane(side); }
  double sign() const { return side == VaneSide::Right ? 1.0 : -1.0; }
  double twist(double x) const { return p.surface.twist_deg * kDegToRad * x; }

  // The vane's intended shape at domain (u, v): out from the shaft by v times the
  // half-width, dropping by cupping * width * v^2, all twisted about the shaft.
  glm::dvec3 target(double u, double v) const {
    const Shaft::Frame f = shaft.frame(s0 + u * lv, twist(u));
    const double w = half_width(vane(), u);
    return f.p + sign() * v * w * f.lateral - p.surface.cupping * w * v * v * f.dorsal;
  }

  std::unique_ptr<VaneSurface> surface() const {
    const int nc = p.surface.cage_columns, nr = p.surface.cage_rows;
    std::vector<glm::dvec3> F(std::size_t(nc) * nr);
    for (int i = 0; i < nc; ++i)
      for (int j = 0; j < nr; ++j) F[i * nr + j] = target(double(i) / (nc - 1), double(j) / (nr - 1));
    // du x dv is dorsal for the left vane (u up the shaft, v toward -X) and ventral for the right.
    return std::make_unique<VaneSurface>(nc, nr, fit_cage_to_targets(F, nc, nr), side == VaneSide::Left ? 1.0 : -1.0);
  }

  // ds/dv of a barb (s: mm along the vane) leaving at angle theta to the shaft:
  // in flat vane coordinates (s, d = v w(s)) its direction is (cos, sin) theta,
  // so dd/ds = tan theta = w dv/ds + v w'(s).
  double ds_dv(double s, double v, double theta) const {
    const double x = std::clamp(s / lv, 0.0, 1.0);
    const double w = half_width(vane(), x), dw = vane().width.derivative(x) / lv;
    const double tn = std::tan(theta);
    return w / std::max(tn - v * dw, 0.25 * tn);
  }

  // Arc length along the vane of a barb at stations v_j = j/(K-1), by RK2.
  std::vector<double> trace(double root, double theta0) const {
    const int K = p.barb.control_points;
    const double bend = vane().barb_bend_deg * kDegToRad, min_theta = 2 * kDegToRad;
    auto theta = [&](double v) { return std::max(theta0 - bend * v, min_theta); };
    std::vector<double> s(K);
    s[0] = root;
    double cur = root;
    const double h = 1.0 / ((K - 1) * kSubsteps);
    for (int j = 1; j < K; ++j) {
      for (int k = 0; k < kSubsteps; ++k) {
        const double v = ((j - 1) * kSubsteps + k) * h;
        const double mid = cur + 0.5 * h * ds_dv(cur, v, theta(v));
        cur = std::min(cur + h * ds_dv(mid, v + 0.5 * h, theta(v + 0.5 * h)), lv);
      }
      s[j] = cur;
    }
    return s;
  }

  void build(std::uint64_t seed, Feather& out, std::vector<BarbPath>& paths, const VaneSurface& surf) const {
    const int n = p.barb_count(side), K = p.barb.control_points;
    const std::uint64_t side_tag = side == VaneSide::Right ? 1 : 0;
    Rng jitter(Rng::derive(seed, 10 + side_tag));
    Rng loose_rng(Rng::derive(seed, 20 + side_tag));
    Rng split_rng(Rng::derive(p.splits.seed.value_or(Rng::derive(seed, 30)), side_tag));
    const double spacing = lv / n;

    std::vector<double> roots(n);
    std::vector<std::vector<double>> s(n);
    for (int k = 0; k < n; ++k) {
      roots[k] = (k + 0.5) * spacing + p.jitter.spacing * spacing * (jitter.uniform() - 0.5);
      const double theta = std::clamp(vane().angle_deg(roots[k] / lv) + p.jitter.angle_deg * jitter.symmetric(), 2.0,
                                      90.0) * kDegToRad;
      s[k] = trace(roots[k], theta);
    }

    // Splits: barbs on either side of a split point are pushed apart, most at the
    // edge, fading in from 1 - depth and away from the split (falloff > gap/2
    // keeps the push from reordering barbs).
    const double falloff = std::max(3 * spacing, p.splits.gap);
    for (int q = 0; q < p.splits.count; ++q) {
      const double at = split_rng.uniform(0.1, 0.9) * lv;
      for (int k = 0; k < n; ++k) {
        const double dir = roots[k] > at ? 1.0 : -1.0;
        const double amount = 0.5 * p.splits.gap * std::exp(-std::abs(roots[k] - at) / falloff);
        for (int j = 1; j < K; ++j) {
          const double v = double(j) / (K - 1);
          s[k][j] += dir * amount * smoothstep((v - (1 - p.splits.depth)) / p.splits.depth);
        }
      }
    }

    // Afterfeather: loose barbs near the base wave in the vane and lift off it.
    std::vector<double> lift(std::size_t(n) * K, 0.0);
    std::vector<char> loose(n, 0);
    const AfterfeatherParams& af = p.afterfeather;
    if (af.enabled && af.fraction > 0) {
      for (int k = 0; k < n; ++k) {
        const double x = roots[k] / lv;
        if (x >= af.fraction) break;
        loose[k] = 1;
        const double a = 1 - x / af.fraction;
        const double phase = loose_rng.uniform(0, 2 * kPi);
        const double up = (loose_rng.uniform() < 0.5 ? -1.0 : 1.0) * loose_rng.uniform(0.5, 1.0);
        // Still leaving the shaft toward the tip: the wave moves a barb's first
        // point along the shaft by at most half its own step there (where the
        // vane is narrow, a short barb would otherwise start back toward the
        // calamus; tests/layout_invariants_test.cpp).
        const double wave = std::clamp(0.5 * (s[k][1] - s[k][0]) * (K - 1), 0.0, af.wave * a);
        for (int j = 1; j < K; ++j) {
          const double v = double(j) / (K - 1);
          s[k][j] += wave * v * std::sin(2 * kPi * af.waves * v + phase);
          lift[std::size_t(k) * K + j] = af.lift * a * up * v * v;
        }
      }
    }

    // Neighbouring barbs must not cross: restore the order at every station,
    // keeping them at least a tenth of the root spacing apart along the shaft
    // (a barb squeezed onto its neighbour's control points crosses it once the
    // vane surface bends them; tests/layout_invariants_test.cpp).
    const double eps = std::max(1e-6 * lv, 0.1 * spacing);
    for (int j = 1; j < K; ++j) {
      for (int k = 0; k < n; ++k) {
        s[k][j] = std::clamp(s[k][j], k * eps, lv);
        if (k > 0) s[k][j] = std::max(s[k][j], s[k - 1][j] + eps);
      }
      for (int k = n - 1; k >= 0; --k) {
        s[k][j] = std::min(s[k][j], lv - (n - 1 - k) * eps);
        if (k < n - 1) s[k][j] = std::min(s[k][j], s[k + 1][j] - eps);
      }
      s[0][j] = std::max(s[0][j], 0.0);  // rounding in the passes above can leave -1e-20
    }

    barbs_traced += n;
    surface_samples += std::int64_t(n) * K;
    for (int k = 0; k < n; ++k) {
      BarbPath path;
      path.side = side;
      path.loose = loose[k];
      std::vector<glm::dvec3> pos(K);
      std::vector<ControlPoint> cps(K + 2);
      for (int j = 0; j < K; ++j) {
        const double v = double(j) / (K - 1), u = s[k][j] / lv;
        path.uv.push_back({u, v});
        const VaneSurface::Sample smp = surf.eval(u, v);
        // The root is put exactly on the shaft centreline.
        pos[j] = j == 0 ? shaft.curve().eval(shaft.t_at(s0 + roots[k])) : smp.p + lift[std::size_t(k) * K + j] * smp.n;
        ControlPoint& cp = cps[j + 1];
        cp.n = glm::vec3(smp.n);
        // A down barb's barbules shorten toward its tip: its tube narrows to a quarter.
        cp.radius = loose[k] ? float(af.radius * (1.0 - kDownTipNarrowing * smoothstep((v - 1.0) / kDownTipTaper + 1.0)))
                             : float(p.barb.radius_root + (p.barb.radius_tip - p.barb.radius_root) * v);
      }
      const std::vector<glm::dvec3> with_ends = with_phantom_ends(pos);
      for (int j = 0; j < K + 2; ++j) cps[j].p = glm::vec3(with_ends[j]);
      cps[0].n = cps[1].n, cps[0].radius = cps[1].radius;
      cps[K + 1].n = cps[K].n, cps[K + 1].radius = cps[K].radius;

      Curve c;
      c.kind = loose[k] ? CurveKind::Down : CurveKind::Barb;
      c.side = side;
      c.root = float((s0 + roots[k]) / shaft.length());
      c.points = std::move(cps);
      out.curves.push_back(std::move(c));
      paths.push_back(std::move(path));
    }
  }
};

}  // namespace

FeatherBuild build_feather_detailed(const FeatherParams& params, std::uint64_t seed, const std::string& source) {
  validate(params, source);
  const Shaft shaft(params.shaft);
  FeatherBuild b;
  b.shaft_length = shaft.length();
  b.vane_start = std::min(params.shaft.calamus_length, 0.9 * b.shaft_length);
  const double lv = b.shaft_length - b.vane_start;

  Feather& f = b.feather;
  f.provenance.source = source;
  f.provenance.seed = seed;
  f.albedo.color = params.albedo;
  f.left = params.left.substructure;
  f.right = params.right.substructure;
  if (params.afterfeather.enabled && params.afterfeather.fraction > 0) f.down_cover = float(params.afterfeather.cover);

  // Shaft first: radius tapering base to tip, normal the (twisted) dorsal side.
  Curve sc;
  sc.kind = CurveKind::Shaft;
  sc.side = VaneSide::None;
  const auto& cps = shaft.curve().control_points();
  for (std::size_t i = 0; i < cps.size(); ++i) {
    const double s = std::clamp((double(i) - 1) / (cps.size() - 3), 0.0, 1.0) * b.shaft_length;
    const double x = std::clamp((s - b.vane_start) / lv, 0.0, 1.0);
    ControlPoint cp;
    cp.p = glm::vec3(cps[i]);
    cp.radius = float(params.shaft.radius_base + (params.shaft.radius_tip - params.shaft.radius_base) * s / b.shaft_length);
    cp.n = glm::vec3(shaft.frame(s, params.surface.twist_deg * kDegToRad * x).dorsal);
    sc.points.push_back(cp);
  }
  f.curves.push_back(std::move(sc));

  for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
    const VaneBuilder vb{params, shaft, side, b.vane_start, lv};
    auto surf = vb.surface();
    vb.build(seed, f, b.paths, *surf);
    (side == VaneSide::Left ? b.left : b.right) = std::move(surf);
  }
  return b;
}

Feather build_feather(const FeatherParams& params, std::uint64_t seed, const std::string& source) {
  return build_feather_detailed(params, seed, source).feather;
}

}  // namespace plumage
