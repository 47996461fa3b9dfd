// The closed-loop accuracy study (closed_loop.h): generator -> path tracer ->
// degraded JPEG -> analyze_photo -> errors against the generated geometry.
#include "closed_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "plumage/common/constants.h"
#include "plumage/common/median.h"
#include "plumage/common/bspline.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/analysis/analyze.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/random.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/fibre_material.h"
#include "plumage/renderer/light_set.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/scene.h"

namespace plumage::closed_loop {
namespace fs = std::filesystem;

namespace {

constexpr double kMarginFraction = 0.07;  // of the image height, around the feather

// NaN for no readings, so that a bound on it fails.
double median(const std::vector<double>& v) { return plumage::median(v, double(NAN)); }

// ---------------------------------------------------------------------------
// The orthographic top view: feather (X, Y) in mm to photo pixels, whose
// integer coordinates are pixel centres (as OpenCV's and the layout's are).
struct View {
  int width = 0, height = 0;
  double mm_per_px = 0;
  glm::dvec2 centre{0.0};  // feather point at the image centre
  glm::dvec2 to_px(const glm::dvec3& p) const {
    return {(p.x - centre.x) / mm_per_px + 0.5 * width - 0.5,
            0.5 * height - (p.y - centre.y) / mm_per_px - 0.5};
  }
};

View frame_feather(const Feather& f, int long_side) {
  glm::dvec2 lo(1e300), hi(-1e300);
  for (const Curve& c : f.curves)
    for (const ControlPoint& cp : c.points) {
      lo = glm::min(lo, glm::dvec2(cp.p.x, cp.p.y));
      hi = glm::max(hi, glm::dvec2(cp.p.x, cp.p.y));
    }
  View v;
  v.height = long_side;
  v.mm_per_px = (hi.y - lo.y) / (long_side * (1.0 - 2 * kMarginFraction));
  const double w_mm = hi.x - lo.x + 2 * kMarginFraction * long_side * v.mm_per_px;
  v.width = 2 * int(std::ceil(0.5 * w_mm / v.mm_per_px));
  v.centre = 0.5 * (lo + hi);
  return v;
}

// A curve's centreline in photo pixels, `n` samples.
std::vector<glm::dvec2> project_curve(const Curve& c, const View& v, int n) {
  std::vector<glm::dvec3> cps;
  for (const ControlPoint& cp : c.points) cps.emplace_back(cp.p);
  const BSpline3 b(cps);
  std::vector<glm::dvec2> out;
  for (int i = 0; i < n; ++i) out.push_back(v.to_px(b.eval(double(i) / (n - 1))));
  return out;
}

// ---------------------------------------------------------------------------
// Drawing the feathers.
Profile knots(std::vector<glm::dvec2> k) { return Profile(std::move(k)); }

std::string describe(const FeatherParams& p, double mm_per_px) {
  const double sp = p.vane_length() / p.barb_count(VaneSide::Left);
  char s[200];
  std::snprintf(s, sizeof s, "L %.0f mm, w %.0f/%.0f mm, angle %.0f-%.0f deg, %.1f px/barb, bend %+.0f deg",
                p.shaft.length, p.left.width.max_value(), p.right.width.max_value(),
                p.left.angle_deg(0.0), p.left.angle_deg(1.0), sp / mm_per_px, p.shaft.bend_deg);
  return s;
}

}  // namespace

std::vector<FeatherParams> draw_params(int count, std::uint64_t seed, int long_side_px) {
  Rng r(seed);
  std::vector<FeatherParams> out;
  for (int i = 0; i < count; ++i) {
    FeatherParams p = default_feather_params();
    p.name = "closed-loop-" + std::to_string(i + 1);
    const double L = r.uniform(50, 140);
    p.shaft.length = L;
    p.shaft.calamus_length = r.uniform(0.08, 0.18) * L;
    p.shaft.bend_deg = r.uniform(-12, 12);
    p.shaft.arch_deg = r.uniform(0, 5);
    p.shaft.radius_base = r.uniform(0.006, 0.01) * L;
    p.shaft.radius_tip = 0.15 * p.shaft.radius_base;
    // The image is about the length tall: pixel size from the long side.
    const double mm_per_px = L / (long_side_px * (1.0 - 2 * kMarginFraction));
    // Barbs must be resolvable across their own direction (the photo's blur
    // wipes out a grating finer than ~3 px): the spacing across the barbs is
    // drawn, and the spacing along the shaft follows from the smallest angle a
    // barb makes with the shaft anywhere (root angle less its bend).
    const double a0 = r.uniform(35, 65), a1 = std::max(25.0, a0 - r.uniform(5, 20));
    const double bend = r.uniform(0, std::min(8.0, a1 - 20.0));
    const double across = r.uniform(3.5, 6.0) * mm_per_px;
    const double spacing = across / std::sin((a1 - bend) * kPi / 180);  // along the shaft
    for (VaneParams* v : {&p.left, &p.right}) {
      const double w = r.uniform(0.08, 0.22) * L;
      v->width = knots({{0.0, r.uniform(0.3, 0.6) * w},
                        {0.3, r.uniform(0.85, 1.0) * w},
                        {0.6, w},
                        {0.9, r.uniform(0.5, 0.75) * w},
                        {1.0, 0.0}});
      const double da = r.uniform(-3, 3);
      v->angle_deg = knots({{0.0, a0 + da}, {1.0, a1 + da}});
      v->barb_bend_deg = bend;
      v->barbs = std::max(20, int(std::lround(p.vane_length() / spacing)));
      v->barb_density = 0;
      // Rendered barb width: 60 % of the spacing across the barbs, so the vane
      // reads as barbs with gaps between them.
      const double W = 0.6 * across;
      v->substructure = SubstructureParams{40, float(0.25 * W), float(0.05 * W), 45.0f, 10.0f, 0.3f,
                                           float(W)};
    }
    p.barb.radius_root = 0.25 * across;
    p.barb.radius_tip = 0.2 * across;
    p.surface.cupping = r.uniform(0, 0.1);
    p.surface.twist_deg = r.uniform(-5, 5);
    p.afterfeather.enabled = false;
    p.splits.count = 0;
    p.jitter.angle_deg = r.uniform(0, 1.5);
    p.jitter.spacing = r.uniform(0, 0.15);
    const double grey = r.uniform(0.35, 0.7);
    p.albedo = glm::vec3(float(grey * 1.15), float(grey), float(grey * 0.8));
    validate(p, p.name);
    out.push_back(p);
  }
  return out;
}

namespace {

// ---------------------------------------------------------------------------
// Rendering and degrading.
Image render_top_view(Feather f, const View& v, bool dark, const StudyOptions& o, std::uint64_t seed) {
  // As one photographs feathers: on contrasting paper. The drawn (light) colour
  // on the black card, a quarter of it on the white one.
  if (!dark) f.albedo.color *= 0.25f;
  SceneOptions so;
  so.backdrop.enabled = true;
  so.backdrop.albedo = glm::vec3(dark ? 0.03f : 0.8f);
  const Scene scene(f, so);
  // One distant light straight above (a copy stand's lamp): the feather's
  // shadow falls under it, and a delta light leaves only the pixel-filter noise.
  LightSet lights;
  DirectionalLight lamp;
  lamp.to_light = glm::vec3(0.0f, 0.0f, 1.0f);
  lamp.irradiance = glm::vec3(3.0f);
  lights.add(lamp);
  // The study tests geometry, not colour: it keeps the albedo mapping its photos
  // were tuned with (Chiang's dense-hair mapping; with the renderer's default layer
  // mapping a feather on the black card is darker, so its faint vane edge is lost).
  const FibreMaterial material(HairParams{}, AlbedoMap(f.albedo, "."), AlbedoMapping::Chiang2016);
  IntegratorSettings is;
  is.max_depth = o.max_depth;
  const PathIntegrator integrator(scene, lights, material, is);
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.look_at = glm::vec3(float(v.centre.x), float(v.centre.y), 0.0f);
  cs.position = glm::vec3(float(v.centre.x), float(v.centre.y), 1000.0f);
  cs.ortho_height = float(v.height * v.mm_per_px);
  const Camera camera(cs, v.width, v.height, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = o.spp;
  rs.seed = seed;
  rs.progress = false;
  return render(camera, integrator, rs).developed(0.0f);
}

// sRGB in 0..1 -> Gaussian blur -> Gaussian noise -> JPEG at `path`.
void degrade_and_write(const Image& linear, const Degradation& d, std::uint64_t seed,
                       const fs::path& path) {
  const int W = linear.width, H = linear.height;
  std::vector<float> a(std::size_t(W) * H * 3), b(a.size());
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const glm::vec3 c = linear.rgb(x, y);
      for (int k = 0; k < 3; ++k)
        a[(std::size_t(y) * W + x) * 3 + k] = linear_to_srgb(std::clamp(c[k], 0.0f, 1.0f));
    }
  if (d.blur_sigma_px > 0) {
    const int r = int(std::ceil(3 * d.blur_sigma_px));
    std::vector<float> k(2 * r + 1);
    float sum = 0;
    for (int i = -r; i <= r; ++i)
      sum += k[i + r] = float(std::exp(-0.5 * i * i / (d.blur_sigma_px * d.blur_sigma_px)));
    for (float& w : k) w /= sum;
    auto pass = [&](const std::vector<float>& in, std::vector<float>& out, int dx, int dy) {
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          for (int c = 0; c < 3; ++c) {
            float s = 0;
            for (int i = -r; i <= r; ++i) {
              const int xx = std::clamp(x + i * dx, 0, W - 1), yy = std::clamp(y + i * dy, 0, H - 1);
              s += k[i + r] * in[(std::size_t(yy) * W + xx) * 3 + c];
            }
            out[(std::size_t(y) * W + x) * 3 + c] = s;
          }
    };
    pass(a, b, 1, 0);
    pass(b, a, 0, 1);
  }
  Rng rng(seed);
  // The photo's 8-bit codes, held as the linear values write_image encodes back to them.
  Image photo(W, H, 3);
  for (std::size_t i = 0; i < a.size(); ++i) {
    // Box-Muller from the generator's portable uniforms.
    const double u1 = std::max(rng.uniform(), 1e-12), u2 = rng.uniform();
    const double n = std::sqrt(-2 * std::log(u1)) * std::cos(2 * kPi * u2);
    const long code = std::lround(255.0 * std::clamp(a[i] + d.noise_sigma * n, 0.0, 1.0));
    photo.pixels[i] = srgb_to_linear(float(code) / 255.0f);
  }
  write_image(path, photo, d.jpeg_quality);
}

// ---------------------------------------------------------------------------
// Truth: the generated geometry in photo pixels.
struct Polyline {
  std::vector<glm::dvec2> p;
  std::vector<double> s;  // arc length at each point
  explicit Polyline(std::vector<glm::dvec2> pts) : p(std::move(pts)), s(p.size(), 0.0) {
    for (std::size_t i = 1; i < p.size(); ++i) s[i] = s[i - 1] + glm::length(p[i] - p[i - 1]);
  }
  double length() const { return s.back(); }
  // Point and unit tangent at arc length a (clamped).
  glm::dvec2 at(double a, glm::dvec2* tangent = nullptr) const {
    a = std::clamp(a, 0.0, length());
    std::size_t i = std::upper_bound(s.begin(), s.end(), a) - s.begin();
    i = std::clamp<std::size_t>(i, 1, p.size() - 1);
    const double seg = std::max(s[i] - s[i - 1], 1e-12);
    if (tangent) *tangent = (p[i] - p[i - 1]) / seg;
    return p[i - 1] + (a - s[i - 1]) / seg * (p[i] - p[i - 1]);
  }
  // Nearest point: its arc length, distance, and signed offset along the
  // normal (-T.y, T.x) (the feather's +X side in the image).
  void project(const glm::dvec2& q, double& arc, double& dist, double& offset) const {
    dist = 1e300;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
      const glm::dvec2 ab = p[i + 1] - p[i];
      const double L2 = std::max(glm::dot(ab, ab), 1e-24);
      const double t = std::clamp(glm::dot(q - p[i], ab) / L2, 0.0, 1.0);
      const glm::dvec2 foot = p[i] + t * ab;
      const double d = glm::length(q - foot);
      if (d < dist) {
        dist = d;
        arc = s[i] + t * (s[i + 1] - s[i]);
        const glm::dvec2 T = ab / std::sqrt(L2);
        offset = glm::dot(q - foot, glm::dvec2(-T.y, T.x));
      }
    }
  }
};

// A 0/1 raster.
struct Mask {
  int w, h;
  std::vector<unsigned char> v;
  Mask(int w_, int h_) : w(w_), h(h_), v(std::size_t(w_) * h_, 0) {}
  bool at(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h && v[std::size_t(y) * w + x]; }
  // Pixels whose centre lies within r of the segment ab.
  void segment(glm::dvec2 a, glm::dvec2 b, double r) {
    const int x0 = std::max(0, int(std::floor(std::min(a.x, b.x) - r))),
              x1 = std::min(w - 1, int(std::ceil(std::max(a.x, b.x) + r)));
    const int y0 = std::max(0, int(std::floor(std::min(a.y, b.y) - r))),
              y1 = std::min(h - 1, int(std::ceil(std::max(a.y, b.y) + r)));
    const glm::dvec2 ab = b - a;
    const double L2 = std::max(glm::dot(ab, ab), 1e-24);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const glm::dvec2 q(x, y);
        const double t = std::clamp(glm::dot(q - a, ab) / L2, 0.0, 1.0);
        if (glm::length(q - (a + t * ab)) <= r) v[std::size_t(y) * w + x] = 1;
      }
  }
  // Pixels whose centre lies inside the polygon (even-odd rule).
  void polygon(const std::vector<glm::dvec2>& P) {
    double ylo = 1e300, yhi = -1e300;
    for (const auto& q : P) ylo = std::min(ylo, q.y), yhi = std::max(yhi, q.y);
    std::vector<double> xs;
    for (int y = std::max(0, int(std::ceil(ylo))); y <= std::min(h - 1, int(std::floor(yhi))); ++y) {
      xs.clear();
      for (std::size_t i = 0; i < P.size(); ++i) {
        const glm::dvec2 a = P[i], b = P[(i + 1) % P.size()];
        if ((a.y <= y) != (b.y <= y)) xs.push_back(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
      }
      std::sort(xs.begin(), xs.end());
      for (std::size_t i = 0; i + 1 < xs.size(); i += 2)
        for (int x = std::max(0, int(std::ceil(xs[i]))); x <= std::min(w - 1, int(std::floor(xs[i + 1])));
             ++x)
          v[std::size_t(y) * w + x] = 1;
    }
  }
};

struct BarbSegment {
  int side;           // -1 left, +1 right
  double s, o;        // arc length along the truth shaft and signed offset (px)
  double angle_deg;   // to the shaft tangent toward the tip, pointing away from the shaft
  double length;      // px
};

struct Truth {
  std::vector<double> shaft_radius_px;  // along `shaft`, for the width test
  Polyline shaft{{{0, 0}, {0, 1}}};
  Mask mask{1, 1};
  std::vector<BarbSegment> segments;
  std::vector<double> roots[2];  // arc lengths of the barb roots, left and right, sorted
};

Truth make_truth(const Feather& f, const View& v, const StudyOptions& o) {
  Truth t;
  t.mask = Mask(v.width, v.height);
  const Curve* shaft = f.shaft();
  std::vector<glm::dvec2> sp = project_curve(*shaft, v, 400);
  for (auto& q : sp) q.x += o.perturb_truth_shaft_px;
  t.shaft = Polyline(sp);
  {
    // Shaft at its radius (radii interpolated along the control points).
    const int n = int(sp.size());
    for (int i = 0; i + 1 < n; ++i) {
      const double x = double(i) / (n - 1) * (shaft->points.size() - 1);
      const auto k = std::min<std::size_t>(std::size_t(x), shaft->points.size() - 2);
      const double r = shaft->points[k].radius +
                       (x - k) * (shaft->points[k + 1].radius - shaft->points[k].radius);
      t.mask.segment(sp[i], sp[i + 1], r / v.mm_per_px);
    }
  }
  // Barbs: each at its rendered half-width, and the gap between neighbours on a
  // side filled (the vane is one surface; light through the gaps is not "outside").
  std::vector<std::vector<glm::dvec2>> barbs[2];
  for (const Curve& c : f.curves) {
    if (c.kind != CurveKind::Barb) continue;
    const int side = c.side == VaneSide::Right ? 1 : -1;
    std::vector<glm::dvec2> b = project_curve(c, v, 40);
    const float W = f.substructure(c.side).ribbon_width;
    for (std::size_t i = 0; i + 1 < b.size(); ++i) {
      const double r = (W > 0 ? 0.5 * W : c.points[0].radius) / v.mm_per_px;
      t.mask.segment(b[i], b[i + 1], r);
      const glm::dvec2 m = 0.5 * (b[i] + b[i + 1]);
      double arc = 0, dist = 0, off = 0;
      t.shaft.project(m, arc, dist, off);
      glm::dvec2 T;
      t.shaft.at(arc, &T);
      // In the unrolled frame (rows: arc length toward the tip; columns: offset).
      glm::dvec2 d = b[i + 1] - b[i];
      const double ds = glm::dot(d, T), dof = glm::dot(d, glm::dvec2(-T.y, T.x)) * side;
      const double len = std::hypot(ds, dof);
      if (len <= 0) continue;
      const double ang = std::acos(std::clamp((dof >= 0 ? ds : -ds) / len, -1.0, 1.0)) * 180 / kPi;
      t.segments.push_back({side, arc, off, ang * o.perturb_truth_angle, len});
    }
    double arc = 0, dist = 0, off = 0;
    t.shaft.project(b.front(), arc, dist, off);
    t.roots[side > 0].push_back(arc);
    barbs[side > 0].push_back(std::move(b));
  }
  for (int k = 0; k < 2; ++k) {
    std::sort(t.roots[k].begin(), t.roots[k].end());
    auto& bs = barbs[k];
    for (std::size_t i = 0; i + 1 < bs.size(); ++i) {
      std::vector<glm::dvec2> quad(bs[i]);
      quad.insert(quad.end(), bs[i + 1].rbegin(), bs[i + 1].rend());
      t.mask.polygon(quad);
    }
  }
  return t;
}

// Outermost truth-mask pixel along the normal at arc length a, on `side`.
double truth_half_width(const Truth& t, double a, int side) {
  glm::dvec2 T;
  const glm::dvec2 C = t.shaft.at(a, &T), N = glm::dvec2(-T.y, T.x) * double(side);
  double w = 0;
  const double reach = 0.5 * (t.mask.w + t.mask.h);
  for (double d = 0; d < reach; d += 0.5) {
    const glm::dvec2 q = C + d * N;
    if (t.mask.at(int(std::lround(q.x)), int(std::lround(q.y)))) w = d;
  }
  return w;
}

// ---------------------------------------------------------------------------
// Scoring.
void score(CaseResult& r, const Truth& t, const PhotoAnalysis& A, const View& v) {
  const FeatherLayout& f = A.layout.feathers.at(0);
  const double Lpx = t.shaft.length();
  // Analysed shaft in photo pixels, densely, and the symmetric worst distance.
  std::vector<glm::dvec2> ap;
  // The layout's photo pixels have their origin at the image's corner; the truth
  // (View::to_px, Mask) puts pixel (i, j)'s centre at (i, j).
  for (int i = 0; i <= 400; ++i)
    ap.push_back(apply(f.image_from_feather, f.shaft_mm.eval(i / 400.0)) - glm::dvec2(0.5));
  const Polyline found(ap);
  double worst = 0;
  for (const auto& q : found.p) {
    double a, d, o;
    t.shaft.project(q, a, d, o);
    worst = std::max(worst, d);
  }
  for (const auto& q : t.shaft.p) {
    double a, d, o;
    found.project(q, a, d, o);
    worst = std::max(worst, d);
  }
  r.shaft = worst / Lpx;

  // Outline: the analysis mask against the truth raster.
  const Image& M = A.masks.at(0);
  const int bx = f.bbox_px[0], by = f.bbox_px[1];
  long inter = 0, uni = 0;
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      const bool truth = t.mask.at(x, y);
      const bool got = x >= bx && y >= by && x < bx + M.width && y < by + M.height &&
                       M.at(x - bx, y - by)[0] > 0.5f;
      inter += truth && got;
      uni += truth || got;
    }
  r.iou = uni ? double(inter) / uni : 0.0;

  // Stations: the analysis's own window (measure_vanes: half a station apart,
  // spacing over at least +-48 px), placed on the truth shaft by projection.
  const Thresholds th;
  const int n = int(f.stations_t.size());
  const double h = std::max(2.0, found.length() / (2.0 * n)), hw = std::max(h, 48.0);
  std::vector<double> angle_err, spacing_err, width_err;
  for (int k = 0; k < n; ++k) {
    double a = 0, d = 0, o = 0;
    t.shaft.project(found.at(f.stations_t[k] * found.length()), a, d, o);
    for (int side : {-1, 1}) {
      const VaneProfile& P = side < 0 ? f.left : f.right;
      std::vector<double> ws;
      for (double j = a - h; j <= a + h; j += 1.0) ws.push_back(truth_half_width(t, j, side));
      const double w = median(ws);
      const double shaft_r = 0.5 * f.shaft_width_mm / v.mm_per_px;
      if (P.width_confidence[k] >= th.width) {
        width_err.push_back(std::fabs(P.width_mm[k] / v.mm_per_px - w) / Lpx);
        ++r.width_used;
      } else {
        ++r.width_low_conf;
      }
      // Barb angle: the barb segments the analysis's window covers (rows a +- h,
      // 15..85% of the width out from the shaft), their length-weighted mean.
      double sum = 0, wsum = 0;
      const double inner = std::max(2 * shaft_r, 0.15 * w), outer = 0.85 * w;
      for (const BarbSegment& s : t.segments)
        if (s.side == side && std::fabs(s.s - a) <= h && s.o * side >= inner && s.o * side <= outer)
          sum += s.angle_deg * s.length, wsum += s.length;
      if (wsum < 2 * h) {
        ++r.angle_no_truth;
      } else if (P.barb_angle_confidence[k] < th.angle) {
        ++r.angle_low_conf;
      } else {
        angle_err.push_back(std::fabs(P.barb_angle_deg[k] - sum / wsum));
        ++r.angle_used;
      }
      // Spacing: neighbouring roots within the window.
      const auto& roots = t.roots[side > 0];
      std::vector<double> gaps;
      for (std::size_t i = 0; i + 1 < roots.size(); ++i)
        if (std::fabs(roots[i] - a) <= hw && std::fabs(roots[i + 1] - a) <= hw)
          gaps.push_back(roots[i + 1] - roots[i]);
      if (gaps.size() < 3 || w < 4 * shaft_r) {
        ++r.spacing_no_truth;
      } else if (P.barb_spacing_confidence[k] < th.spacing) {
        ++r.spacing_low_conf;
      } else {
        const double truth = median(gaps);
        spacing_err.push_back(std::fabs(P.barb_spacing_mm[k] / v.mm_per_px - truth) / truth);
        ++r.spacing_used;
      }
    }
  }
  auto max_of = [](const std::vector<double>& e) {
    return e.empty() ? NAN : *std::max_element(e.begin(), e.end());
  };
  r.angle_deg = median(angle_err);
  r.angle_max_deg = max_of(angle_err);
  r.spacing = median(spacing_err);
  r.spacing_max = max_of(spacing_err);
  r.width = max_of(width_err);
}

// The truth drawn over the analysis overlay: shaft and outline in magenta.
Image overlay_with_truth(const PhotoAnalysis& A, const Truth& t) {
  Image img = A.overlay;
  auto dot = [&](double x, double y) {
    const int ix = int(std::lround(x)), iy = int(std::lround(y));
    if (ix >= 0 && iy >= 0 && ix < img.width && iy < img.height) img.set_rgb(ix, iy, {1.0f, 0.0f, 1.0f});
  };
  for (double a = 0; a <= t.shaft.length(); a += 3.0) {
    const glm::dvec2 q = t.shaft.at(a);
    dot(q.x, q.y);
  }
  for (int y = 1; y + 1 < t.mask.h; ++y)
    for (int x = 1; x + 1 < t.mask.w; ++x)
      if (t.mask.at(x, y) && (!t.mask.at(x - 1, y) || !t.mask.at(x + 1, y) || !t.mask.at(x, y - 1) ||
                              !t.mask.at(x, y + 1)) && (x + y) % 3 == 0)
        dot(x, y);
  return img;
}

}  // namespace

bool CaseResult::passes(const Bounds& b) const {
  // NaN (nothing compared) fails.
  return shaft <= b.shaft && angle_deg <= b.angle_deg && spacing <= b.spacing && width <= b.width &&
         iou >= b.iou;
}

CaseResult run_case(const FeatherParams& params, int index, bool dark, const StudyOptions& o) {
  const std::uint64_t seed = Rng::derive(o.seed, std::uint64_t(index));
  const Feather feather = build_feather(params, seed, "closed-loop");
  const View v = frame_feather(feather, o.long_side_px);
  CaseResult r;
  r.feather = index;
  r.dark = dark;
  r.length_mm = params.shaft.length;
  r.mm_per_px = v.mm_per_px;
  r.summary = describe(params, v.mm_per_px);
  const Image linear = render_top_view(feather, v, dark, o, seed);
  r.photo = o.work_dir / ("feather" + std::to_string(index) + (dark ? "-black" : "-white") + ".jpg");
  degrade_and_write(linear, o.degrade, Rng::derive(seed, dark ? 2 : 1), r.photo);

  AnalyzeOptions ao;
  ao.mm_per_px = v.mm_per_px;
  const PhotoAnalysis A = analyze_photo(r.photo, ao);
  if (A.layout.feathers.size() != 1)
    throw Error(Location{r.photo.string()},
                "expected one feather, the analysis found " + std::to_string(A.layout.feathers.size()));
  const Truth truth = make_truth(feather, v, o);
  score(r, truth, A, v);
  r.overlay = overlay_with_truth(A, truth);
  if (o.keep_overlays) {
    fs::path ov = r.photo;
    write_image(ov.replace_extension(".overlay.png"), r.overlay);
  }
  return r;
}

std::vector<CaseResult> run_study(const StudyOptions& o) {
  const std::vector<FeatherParams> params = draw_params(o.feathers, o.seed, o.long_side_px);
  std::vector<CaseResult> out;
  for (int i = 0; i < o.feathers; ++i)
    if (!o.only || *o.only == i + 1)
      for (bool dark : {false, true}) out.push_back(run_case(params[i], i + 1, dark, o));
  return out;
}

std::string report_markdown(const std::vector<CaseResult>& rs, const StudyOptions& o, const Bounds& b) {
  std::ostringstream m;
  char line[512];
  std::snprintf(line, sizeof line,
                "%d feathers (seed %llu), each on white and on black: %d px tall, %d spp, "
                "blur sigma %.1f px, noise sigma %.3f, JPEG quality %d.\n\n",
                o.feathers, static_cast<unsigned long long>(o.seed), o.long_side_px, o.spp,
                o.degrade.blur_sigma_px, o.degrade.noise_sigma, o.degrade.jpeg_quality);
  m << line;
  m << "| # | feather | card | shaft (<= " << b.shaft * 100 << "% L) | angle median / max (<= "
    << b.angle_deg << " deg) | spacing median / max (<= " << b.spacing * 100
    << "%) | width max (<= " << b.width * 100 << "% L) | IoU (>= " << b.iou
    << ") | compared: angle, spacing, width | left out, low confidence | left out, no vane | |\n";
  m << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const CaseResult& r : rs) {
    std::snprintf(line, sizeof line,
                  "| %d | %s | %s | %.2f%% | %.2f / %.2f | %.1f%% / %.1f%% | %.2f%% | %.3f | %d, %d, %d | "
                  "%d, %d, %d | %d, %d | %s |\n",
                  r.feather, r.summary.c_str(), r.dark ? "black" : "white", 100 * r.shaft, r.angle_deg,
                  r.angle_max_deg, 100 * r.spacing, 100 * r.spacing_max, 100 * r.width, r.iou,
                  r.angle_used, r.spacing_used, r.width_used, r.angle_low_conf, r.spacing_low_conf,
                  r.width_low_conf, r.angle_no_truth, r.spacing_no_truth, r.passes(b) ? "ok" : "**fails**");
    m << line;
  }
  auto stat = [&](auto get, bool worst_is_min) {
    std::vector<double> v;
    for (const CaseResult& r : rs) v.push_back(get(r));
    std::sort(v.begin(), v.end());
    return std::pair{worst_is_min ? v.front() : v.back(), v[v.size() / 2]};
  };
  const auto sh = stat([](const CaseResult& r) { return r.shaft; }, false);
  const auto an = stat([](const CaseResult& r) { return r.angle_deg; }, false);
  const auto spc = stat([](const CaseResult& r) { return r.spacing; }, false);
  const auto wd = stat([](const CaseResult& r) { return r.width; }, false);
  const auto io = stat([](const CaseResult& r) { return r.iou; }, true);
  std::snprintf(line, sizeof line,
                "\nOver all %zu cases, worst / median: shaft %.2f%% / %.2f%% of L; angle %.2f / %.2f deg; "
                "spacing %.1f%% / %.1f%%; width %.2f%% / %.2f%% of L; IoU %.3f / %.3f.\n",
                rs.size(), 100 * sh.first, 100 * sh.second, an.first, an.second, 100 * spc.first,
                100 * spc.second, 100 * wd.first, 100 * wd.second, io.first, io.second);
  m << line;
  return m.str();
}

}  // namespace plumage::closed_loop
