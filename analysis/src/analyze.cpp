// Photo analysis driver: load, segment, scale, then per feather shaft, vanes,
// albedo and the overlay; and the all-or-nothing writer of its outputs.
#include "plumage/analysis/analyze.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>
#include <tuple>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/number_text.h"
#include "plumage/layout/rules.h"
#include "albedo.h"
#include "grid_scale.h"
#include "overlay.h"
#include "photo.h"
#include "quills.h"
#include "segmentation.h"
#include "shaft.h"
#include "vane.h"

namespace plumage {
namespace fs = std::filesystem;
using namespace analysis;

namespace {

glm::dmat3x2 inverse_affine(const glm::dmat3x2& A) {
  const glm::dmat2 L(A[0], A[1]);
  const glm::dmat2 Li = glm::inverse(L);
  return glm::dmat3x2(Li[0], Li[1], -(Li * A[2]));
}

// Feather coordinates (DESIGN §3) from photo pixels: the photo seen as the
// dorsal side (its y axis flipped up), rotated so the calamus->tip chord is +Y,
// scaled to mm and moved so the calamus is the origin.
glm::dmat3x2 feather_from_photo(const glm::dvec2& calamus, const glm::dvec2& tip,
                                double mm_per_px) {
  const glm::dvec2 qc(calamus.x, -calamus.y), qt(tip.x, -tip.y);
  const glm::dvec2 d = glm::normalize(qt - qc), X(d.y, -d.x);
  const double s = mm_per_px;
  return glm::dmat3x2(glm::dvec2(s * X.x, s * d.x), glm::dvec2(-s * X.y, -s * d.y),
                      glm::dvec2(-s * glm::dot(X, qc), -s * glm::dot(d, qc)));
}

// The analysis works in OpenCV's pixels, whose pixel (i, j) has its centre at (i, j),
// on the photo downscaled by `ds`; the layout's photo pixels have their origin at the
// top-left corner of the top-left pixel (docs/layout-format.md), so that the centre of
// working pixel (i, j) lies at ((i + 1/2) / ds, (j + 1/2) / ds) in them.
glm::dvec2 photo_from_work(const glm::dvec2& p, double ds) { return (p + 0.5) / ds; }
// A working-pixel box as the photo pixels that hold it (x, y, w, h).
std::array<int, 4> photo_box(const cv::Rect& box, double ds) {
  return {int(std::floor(box.x / ds)), int(std::floor(box.y / ds)), int(std::ceil(box.width / ds)),
          int(std::ceil(box.height / ds))};
}

std::vector<double> scaled(const std::vector<double>& v, double k) {
  std::vector<double> out(v);
  for (double& x : out) x *= k;
  return out;
}
std::vector<double> clamped01(const std::vector<double>& v) {
  std::vector<double> out(v);
  for (double& x : out) x = std::clamp(std::isfinite(x) ? x : 0.0, 0.0, 1.0);
  return out;
}

VaneProfile to_profile(const SideMeasure& s, double mm_per_px) {
  VaneProfile p;
  p.width_mm = scaled(s.width_px, mm_per_px);
  p.width_confidence = clamped01(s.width_conf);
  p.barb_angle_deg = s.angle_deg;
  p.barb_angle_confidence = clamped01(s.angle_conf);
  p.barb_spacing_mm = scaled(s.spacing_px, mm_per_px);
  p.barb_spacing_confidence = clamped01(s.spacing_conf);
  return p;
}

Image to_image_linear(const cv::Mat& bgr) {
  float lut[256];
  for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(i / 255.0f);
  Image img(bgr.cols, bgr.rows, 3);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      img.set_rgb(x, y, {lut[p[2]], lut[p[1]], lut[p[0]]});
    }
  return img;
}

}  // namespace

namespace {
// Accumulates wall time per named stage.
class StageClock {
 public:
  explicit StageClock(std::vector<std::pair<std::string, double>>& out) : out_(out) {}
  void lap(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    for (auto& [name, t] : out_)
      if (name == stage) return void(t += s);
    out_.emplace_back(stage, s);
  }

 private:
  std::vector<std::pair<std::string, double>>& out_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};
}  // namespace

namespace {
// Shaft, vanes and albedo of one feather, appended to the layout and the overlay list.
void analyze_feather(const Photo& photo, const Segmentation& seg, const Component& comp, const Shaft& shaft,
                     int k, const AnalyzeOptions& opt, Layout& L, PhotoAnalysis& out,
                     std::vector<OverlayFeather>& drawn, StageClock& clock);
}  // namespace

PhotoAnalysis analyze_photo(const fs::path& photo_path, const AnalyzeOptions& opt) {
  const Location where{photo_path.string()};
  PhotoAnalysis out;
  StageClock clock(out.stage_seconds);
  if (opt.mm_per_px && !(*opt.mm_per_px > 0 && std::isfinite(*opt.mm_per_px)))
    throw Error("--mm-per-px must be a positive number of millimetres per pixel");
  if (!(opt.grid_mm > 0)) throw Error("--grid-mm must be positive");
  if (opt.stations < 2 || opt.stations > 1000) throw Error("stations must be in 2..1000");
  Photo photo = load_photo(photo_path, opt.max_megapixels, opt.refuse_megapixels);
  const double ds = photo.downscale;
  clock.lap("load");

  const Segmentation seg = segment_feathers(photo.bgr);
  clock.lap("segment");
  if (seg.feathers.empty()) {
    std::ostringstream m;
    m << "no feather found (background " << (seg.dark_background ? "dark" : "light")
      << ", nothing stands out from it by more than " << std::lround(seg.threshold)
      << "/255 over a feather-sized area); photograph the feather on plain, contrasting paper";
    throw Error(where, m.str());
  }
  // Quills first: a region whose quills stand in a row is a shingled row, cut into
  // one feather per quill; its pieces take the ids after the regions', in the
  // order of their quills along the row (docs/analysis.md, "Shingled rows").
  const int regions = int(seg.feathers.size());
  struct RowOfQuills {
    int quills = 0;                 // in a row; 0: no row
    int first_id = 0, last_id = 0;  // its feathers' ids, when it was cut
    std::string not_followed;       // why it was not, when it was not
  };
  std::vector<RowOfQuills> rows(static_cast<std::size_t>(regions));
  std::vector<Component> pieces;  // ids regions + 1, ...
  for (int k = 1; k <= regions; ++k) {
    const Component& comp = seg.feathers[std::size_t(k - 1)];
    if (comp.touches_border && !opt.allow_border) continue;
    const std::vector<Quill> quills = quills_of_a_row(find_quills(comp));
    if (quills.size() < 2) continue;
    RowOfQuills& row = rows[std::size_t(k - 1)];
    row.quills = int(quills.size());
    RowSplit split = split_by_quills(comp, quills, photo.bgr.size());
    if (split.pieces.empty()) {
      row.not_followed = split.why;
      continue;
    }
    row.first_id = regions + int(pieces.size()) + 1;
    row.last_id = regions + int(pieces.size() + split.pieces.size());
    for (Component& c : split.pieces) c.row_region = k, pieces.push_back(std::move(c));
  }
  clock.lap("quills");
  const int count = regions + int(pieces.size());
  if (opt.feather && (*opt.feather < 1 || *opt.feather > count))
    throw Error(where, "--feather " + std::to_string(*opt.feather) + ": the photo has " +
                           std::to_string(count) + " feather(s); pick 1.." + std::to_string(count));

  Layout& L = out.layout;
  L.source_image = photo_path.string();
  L.image_width = photo.full_width;
  L.image_height = photo.full_height;
  L.analysis_downscale = ds;
  L.background = seg.dark_background ? "dark" : "light";
  for (const auto& n : photo.notes) out.warnings.push_back(n);

  // Scale: given, else a grid in the photo, else the default.
  cv::Mat all = cv::Mat::zeros(photo.bgr.size(), CV_8U);
  for (const Component& c : seg.feathers) all(c.bbox).setTo(255, c.mask);
  GridScale grid;
  if (opt.mm_per_px) {
    L.scale = {*opt.mm_per_px, ScaleSource::Given, 1.0, 0.0, 0.0};
  } else {
    grid = detect_grid(photo.bgr, all | seg.foreground);
    if (grid.found) {
      L.scale = {opt.grid_mm / (grid.period_px / ds), ScaleSource::Grid, grid.confidence,
                 grid.period_px / ds, opt.grid_mm};
    } else {
      // The guess, lowered where a large photo would make its largest region longer
      // than half the longest shaft a feather may have (a 30000-pixel photo of one
      // feather would otherwise give a 3 m feather that no layout reader accepts).
      double longest_px = 0;
      for (const Component& c : seg.feathers) longest_px = std::max(longest_px, std::hypot(c.bbox.width, c.bbox.height) / ds);
      const double cap = longest_px > 0 ? 0.5 * kMaxShaftLengthMm / longest_px : opt.default_mm_per_px;
      const double guess = std::min(opt.default_mm_per_px, cap);
      L.scale = {guess, ScaleSource::Default, 0.1, 0.0, 0.0};
      std::string assumed = num(guess) + " mm per pixel";
      if (guess < opt.default_mm_per_px)
        assumed += " (lowered from " + num(opt.default_mm_per_px) + " so the largest feather is at most " +
                   num(0.5 * kMaxShaftLengthMm) + " mm long)";
      out.warnings.push_back("no grid or ruler found and no --mm-per-px given: assuming " + assumed +
                             ", so every length is a guess");
    }
  }
  const double mm_per_work_px = L.scale.mm_per_px / ds;
  clock.lap("scale");

  std::vector<OverlayFeather> drawn;
  std::vector<OverlaySkipped> skipped_drawn;
  // A region that cannot be analysed is skipped with a warning so the rest of a
  // sheet still is; asked for by --feather, or the only one, it is an error.
  std::string first_refusal;
  auto skip = [&](const Component& comp, int k, const char* reason, const std::string& what,
                  const std::string& fix) {
    std::ostringstream box;
    box << " (box " << std::lround(comp.bbox.x / ds) << "," << std::lround(comp.bbox.y / ds) << " "
        << std::lround(comp.bbox.width / ds) << "x" << std::lround(comp.bbox.height / ds) << " px)";
    const std::string refusal = "feather " + std::to_string(k) + " " + what + box.str() + "; " + fix;
    if (opt.feather) throw Error(where, refusal);
    if (first_refusal.empty()) first_refusal = refusal;
    SkippedRegion s;
    s.id = k;
    s.bbox_px = photo_box(comp.bbox, ds);
    s.reason = reason;
    s.message = "skipped: " + what + box.str();
    out.warnings.push_back("feather " + std::to_string(k) + " " + s.message);
    L.skipped.push_back(std::move(s));
    skipped_drawn.push_back({k, comp.contour, std::string(reason) == "touches_border"});
  };
  // A region that holds several feathers, told by segmentation or by the shaft tracer.
  auto skip_several = [&](const Component& comp, int k, const std::string& what) {
    skip(comp, k, "unseparated", what,
         "lay them apart on the card and photograph them again, or pick another with --feather");
  };
  for (int k = 1; k <= count; ++k) {
    const RowOfQuills* row = k <= regions ? &rows[std::size_t(k - 1)] : nullptr;
    if (opt.feather && *opt.feather != k && !(row && row->first_id > 0)) continue;
    const Component& comp = k <= regions ? seg.feathers[std::size_t(k - 1)] : pieces[std::size_t(k - regions - 1)];
    if (row && row->first_id > 0) {
      // Not analysed as one: its feathers are, under their own ids.
      const std::string ids = std::to_string(row->first_id) + "-" + std::to_string(row->last_id);
      if (opt.feather && *opt.feather == k)
        throw Error(where, "--feather " + std::to_string(k) + " is a shingled row, analysed as feathers " + ids +
                               " (one per quill); pick one of them");
      if (opt.feather) continue;
      SkippedRegion s;
      s.id = k;
      s.bbox_px = photo_box(comp.bbox, ds);
      s.reason = "split_row";
      s.message = "a shingled row of " + std::to_string(row->last_id - row->first_id + 1) +
                  " feathers, analysed as feathers " + ids + " (one per quill)";
      L.skipped.push_back(std::move(s));
      continue;
    }
    if (row && !row->not_followed.empty()) {
      // Several feathers either way; the shaft tracer's reason (a fan, a row's
      // tips or lines) names them better when it has one.
      std::string why;
      try {
        if (const Shaft traced = trace_shaft(photo.bgr, comp); traced.several_feathers())
          why = traced.several_feathers_why();
      } catch (const Error&) {
      }
      skip_several(comp, k, !why.empty() ? why
                                         : "holds " + std::to_string(row->quills) +
                                               " quills side by side (a shingled row) that could not be followed: " +
                                               row->not_followed);
      continue;
    }
    if (comp.touches_border && !opt.allow_border) {
      skip(comp, k, "touches_border", "touches the image border, so it may be cut off",
           "photograph it with a margin, pick another with --feather, or pass --allow-border to "
           "analyse it anyway");
      continue;
    }
    if (comp.unseparated) {
      std::ostringstream what;
      if (comp.faint_pieces > 0)
        what << "is faint feathers whose colour clears the threshold in " << comp.faint_pieces
             << " patches joined by fluff below it, so they could not be told apart";
      else
        what << "is several feathers that touch or overlap and could not be told apart ("
             << (comp.cores > 1 ? std::to_string(comp.cores) + " cores" : "fills " +
                 std::to_string(int(std::lround(100 * comp.solidity))) + " % of its hull") << ")";
      skip_several(comp, k, what.str());
      continue;
    }
    try {
      const Shaft shaft = trace_shaft(photo.bgr, comp);
      if (shaft.several_feathers()) {
        skip_several(comp, k, shaft.several_feathers_why());
        continue;
      }
      if (comp.row_feathers > 0) {
        out.warnings.push_back("feather " + std::to_string(k) + ": one of a shingled row of " +
                               std::to_string(comp.row_feathers) + " (region " + std::to_string(comp.row_region) +
                               "), cut out along the quills; where its neighbours cover or meet it, its vane "
                               "width is the generator's prior");
      }
      if (comp.separated_from > 0) {
        std::ostringstream cut;
        cut << "feather " << k << ": cut out of " << comp.separated_from
            << " touching feathers along the neck between them; where they overlapped its vane may be clipped";
        out.warnings.push_back(cut.str());
      }
      analyze_feather(photo, seg, comp, shaft, k, opt, L, out, drawn, clock);
      if (comp.row_feathers > 0) L.feathers.back().row = {comp.row_region, comp.row_feathers};
    } catch (const Error& e) {
      // Errors from inside a stage do not know the file; name it and the feather.
      if (!e.where().file.empty()) throw;
      throw Error(where, "feather " + std::to_string(k) + ": " + e.message());
    }
  }
  if (L.feathers.empty()) throw Error(where, first_refusal);
  out.overlay = to_image_linear(draw_overlay(photo.bgr, drawn, skipped_drawn, mm_per_work_px,
                                             L.scale, grid, seg.foreground));
  clock.lap("overlay");
  return out;
}

namespace {

constexpr int kShaftControlPoints = 6;

// A shingled row's feather: the stations where a side's edge is one of the row's
// other feathers, not the card (within 2 px past the measured width), are hidden:
// width confidence 0, so the generator's prior builds the width there.
void mark_hidden_stations(const Component& comp, const BSpline2& shaft_px, const VaneMeasure& vm, FeatherLayout& f) {
  cv::Mat rest;
  cv::dilate(comp.row_rest, rest, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  for (auto [side, measure, profile] : {std::tuple{-1, &vm.left, &f.left}, std::tuple{+1, &vm.right, &f.right}}) {
    profile->width_hidden.assign(vm.t.size(), 0.0);
    for (std::size_t i = 0; i < vm.t.size(); ++i) {
      const glm::dvec2 C = shaft_px.eval(vm.t[i]);
      const glm::dvec2 T = glm::normalize(shaft_px.deriv(vm.t[i]));
      const glm::dvec2 N = double(side) * glm::dvec2(-T.y, T.x);  // the feather's +X side is (-T.y, T.x)
      const glm::dvec2 E = C + (measure->width_px[i] + 1.0) * N;
      const int x = int(std::lround(E.x)) - comp.bbox.x, y = int(std::lround(E.y)) - comp.bbox.y;
      if (x < 0 || y < 0 || x >= rest.cols || y >= rest.rows || !rest.at<uchar>(y, x)) continue;
      profile->width_hidden[i] = 1.0;
      profile->width_confidence[i] = 0.0;
    }
  }
}

void analyze_feather(const Photo& photo, const Segmentation& seg, const Component& comp, const Shaft& shaft,
                     int k, const AnalyzeOptions& opt, Layout& L, PhotoAnalysis& out,
                     std::vector<OverlayFeather>& drawn, StageClock& clock) {
  const double ds = photo.downscale;
  const double mm_per_work_px = L.scale.mm_per_px / ds;
  std::vector<glm::dvec2> pts;
  for (const auto& p : shaft.path) pts.push_back({p.x, p.y});
  // Six control points: the rachis bends smoothly, and with eight the fit follows
  // the traced path's few-pixel zig-zag on light paper; the wobble in direction
  // (1-2 deg) tilts the spacing lines across the barbs and swung the spacing by
  // +-10 % along the shaft (closed-loop study, feather 6 on white).
  const BSpline2 shaft_px = fit_spline(pts, kShaftControlPoints);
  clock.lap("shaft");
  const glm::dvec2 cal = photo_from_work(shaft_px.eval(0.0), ds), tip = photo_from_work(shaft_px.eval(1.0), ds);

  FeatherLayout f;
  f.id = k;
  f.bbox_px = photo_box(comp.bbox, ds);
  std::vector<cv::Point> poly;
  cv::approxPolyDP(comp.contour, poly, 0.75, true);
  for (const auto& p : poly) f.outline_px.push_back(photo_from_work(glm::dvec2(p.x, p.y), ds));
  f.feather_from_image = feather_from_photo(cal, tip, L.scale.mm_per_px);
  f.image_from_feather = inverse_affine(f.feather_from_image);
  // feather_from_image after photo_from_work.
  const glm::dmat3x2 f_from_work(f.feather_from_image[0] / ds, f.feather_from_image[1] / ds,
                                 apply(f.feather_from_image, photo_from_work({0.0, 0.0}, ds)));
  std::vector<glm::dvec2> cps;
  for (const auto& c : shaft_px.control_points()) cps.push_back(apply(f_from_work, c));
  f.shaft_mm = BSpline2(cps);
  f.length_mm = spline_length(f.shaft_mm);
  if (!(f.length_mm >= kMinShaftLengthMm && f.length_mm <= kMaxShaftLengthMm)) {
    const char* from = L.scale.source == ScaleSource::Given  ? "given by --mm-per-px"
                       : L.scale.source == ScaleSource::Grid ? "read from the grid"
                                                             : "assumed";
    throw Error("its shaft is " + num(f.length_mm) + " mm long at " + num(L.scale.mm_per_px) +
                                " mm per pixel (" + from + "), outside the [" + num(kMinShaftLengthMm) + ", " +
                                num(kMaxShaftLengthMm) + "] mm a feather may be; give the photo's scale with --mm-per-px");
  }
  f.shaft_width_mm = shaft.width_px * mm_per_work_px;
  f.shaft_confidence = shaft.confidence;
  f.shaft_seen = shaft.seen;

  VaneMeasure vm = measure_vanes(photo.bgr, comp, shaft_px, shaft.width_px, opt.stations);
  f.stations_t = vm.t;
  f.left = to_profile(vm.left, mm_per_work_px);
  f.right = to_profile(vm.right, mm_per_work_px);
  if (comp.row_feathers > 0) mark_hidden_stations(comp, shaft_px, vm, f);
  // Down is told from vane by its texture at the barb scale, so only where the
  // photo resolves barbs (on either side).
  double period_mm = 0;
  for (VaneSide side : {VaneSide::Left, VaneSide::Right})
    if (const auto r = resolved_barb_spacing(f, side); r.mm) period_mm = period_mm > 0 ? std::min(period_mm, *r.mm) : *r.mm;
  if (period_mm > 0) {
    for (auto [measure, profile] : {std::pair{&vm.left, &f.left}, std::pair{&vm.right, &f.right}}) {
      find_downy_base(*measure, vm.t, period_mm / mm_per_work_px);
      profile->afterfeather_to_t = measure->afterfeather_to_t;
    }
  }
  // A plume: both vanes open, the card seen between loose barbs from base to tip
  // (docs/analysis.md, "Plumes: an open vane"); the whole feather is downy.
  const double open_left = vane_open_share(photo.bgr, seg.background_bgr, seg.card_sigma, shaft_px, vm.t, vm.left, -1);
  const double open_right = vane_open_share(photo.bgr, seg.background_bgr, seg.card_sigma, shaft_px, vm.t, vm.right, +1);
  f.left.open_share = open_left;
  f.right.open_share = open_right;
  if (std::min(open_left, open_right) >= kPlumeOpenShare) {
    for (auto [measure, profile] : {std::pair{&vm.left, &f.left}, std::pair{&vm.right, &f.right}}) {
      measure->downy.assign(vm.t.size(), 1);
      measure->afterfeather_to_t = profile->afterfeather_to_t = 1.0;
    }
  }
  clock.lap("vanes");
  f.touches_border = comp.touches_border;
  if (comp.touches_border)
    f.warnings.push_back("touches the image border; the vane may be cut off");

  const AlbedoResult al =
      extract_albedo(photo.bgr, comp, inverse_affine(f_from_work), f.shaft_mm, f.shaft_width_mm,
                     mm_per_work_px, !seg.dark_background, seg.background_bgr);
  f.albedo.file = "feather" + std::to_string(k) + ".albedo.png";  // write_analysis prefixes the stem
  f.albedo.width_px = al.rgba.cols;
  f.albedo.height_px = al.rgba.rows;
  f.albedo.origin_mm = al.origin_mm;
  f.albedo.mm_per_texel = al.mm_per_texel;
  f.albedo.scale = al.scale;
  f.albedo.shaft_rgb = al.shaft_rgb;
  Image tex(al.rgba.cols, al.rgba.rows, 4);
  std::memcpy(tex.pixels.data(), al.rgba.ptr<float>(0), tex.pixels.size() * sizeof(float));
  out.albedo.push_back(std::move(tex));
  clock.lap("albedo");
  Image mask(comp.mask.cols, comp.mask.rows, 1);
  for (int y = 0; y < comp.mask.rows; ++y)
    for (int x = 0; x < comp.mask.cols; ++x) mask.at(x, y)[0] = comp.mask.at<uchar>(y, x) / 255.0f;
  out.masks.push_back(std::move(mask));
  for (const auto& w : f.warnings) out.warnings.push_back("feather " + std::to_string(k) + ": " + w);
  // In layout.json each feather says so; the command's warnings say it once, for the photo.
  if (L.scale.source == ScaleSource::Default) f.warnings.push_back("scale unknown (default used)");

  drawn.push_back({k, comp.contour, shaft_px, vm, f.length_mm, comp.touches_border});
  L.feathers.push_back(std::move(f));
}

}  // namespace

void write_analysis(PhotoAnalysis& a, const fs::path& layout_path, const fs::path& overlay_path) {
  const fs::path dir = layout_path.parent_path();
  const std::string stem = layout_path.stem().string();
  for (std::size_t i = 0; i < a.layout.feathers.size(); ++i)
    a.layout.feathers[i].albedo.file =
        stem + ".feather" + std::to_string(a.layout.feathers[i].id) + ".albedo.png";

  // All or nothing: a failure leaves no partial set of outputs behind.
  FileBatch outputs;
  for (std::size_t i = 0; i < a.layout.feathers.size(); ++i)
    write_image(outputs, dir / a.layout.feathers[i].albedo.file, a.albedo[i]);
  if (!overlay_path.empty()) write_image(outputs, overlay_path, a.overlay);
  outputs.stage_text(layout_path, layout_to_json(a.layout));
  outputs.commit();
}

}  // namespace plumage
