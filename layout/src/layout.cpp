// layout.json reader and writer (format: docs/layout-format.md).
#include "plumage/common/feather.h"
#include "plumage/layout/layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/json_file.h"
#include "plumage/common/json_reader.h"
#include "plumage/common/number_text.h"
#include "plumage/common/text.h"

namespace plumage {
namespace {

using json = nlohmann::json;
constexpr const char* kFormat = "plumage-layout";
constexpr int kVersion = 1;

using ojson = nlohmann::ordered_json;

ojson vec2(const glm::dvec2& p) { return ojson::array({p.x, p.y}); }

ojson affine(const glm::dmat3x2& A) {
  return ojson::array(
      {ojson::array({A[0][0], A[1][0], A[2][0]}), ojson::array({A[0][1], A[1][1], A[2][1]})});
}

// Pretty-printed with the keys in a reading order, and arrays of numbers (or of
// points) kept on one line so a person can scan the file.
bool is_flat(const ojson& j) {
  if (!j.is_array()) return false;
  for (const auto& e : j)
    if (!e.is_primitive() && !(e.is_array() && std::all_of(e.begin(), e.end(), [](const ojson& x) {
                                 return x.is_primitive();
                               })))
      return false;
  return true;
}

void dump(const ojson& j, int indent, std::string& out) {
  const std::string pad(indent + 2, ' ');
  if (j.is_object() && !j.empty()) {
    out += "{\n";
    std::size_t i = 0;
    for (auto it = j.begin(); it != j.end(); ++it, ++i) {
      out += pad + json_text(ojson(it.key())) + ": ";
      dump(it.value(), indent + 2, out);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(indent, ' ') + "}";
  } else if (j.is_array() && !j.empty() && !is_flat(j)) {
    out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      out += pad;
      dump(j[i], indent + 2, out);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(indent, ' ') + "]";
  } else if (j.is_array()) {
    out += "[";
    for (std::size_t i = 0; i < j.size(); ++i) {
      if (i) out += ", ";
      dump(j[i], indent, out);
    }
    out += "]";
  } else if (j.is_number_float()) {
    // Seven significant digits: 0.1 um on a 1 m feather, and stable on re-reading.
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.7g", j.get<double>());
    out += buf;
  } else {
    out += json_text(j);
  }
}

ojson profile(const VaneProfile& v) {
  ojson j = {{"width_mm", v.width_mm},
             {"width_confidence", v.width_confidence},
             {"barb_angle_deg", v.barb_angle_deg},
             {"barb_angle_confidence", v.barb_angle_confidence},
             {"barb_spacing_mm", v.barb_spacing_mm},
             {"barb_spacing_confidence", v.barb_spacing_confidence},
             {"afterfeather_to_t", v.afterfeather_to_t},
             {"open_share", v.open_share}};
  if (!v.width_hidden.empty()) j["width_hidden"] = v.width_hidden;  // only a shingled row's feather
  return j;
}

// --- strict reading: every value through JsonReader, which names its place ----

glm::dvec2 point(const JsonReader& j) {
  const auto v = j.numbers(2);
  return {v[0], v[1]};
}

glm::dmat3x2 matrix(const JsonReader& j) {
  const std::vector<JsonReader> rows = j.elements(2);
  glm::dmat3x2 A;
  for (int r = 0; r < 2; ++r) {
    const auto row = rows[std::size_t(r)].numbers(3);
    for (int c = 0; c < 3; ++c) A[c][r] = row[std::size_t(c)];
  }
  const double det = A[0][0] * A[1][1] - A[1][0] * A[0][1];
  if (!(std::fabs(det) > 1e-12)) j.fail("matrix is singular");
  return A;
}

VaneProfile read_vane(const JsonReader& j, std::size_t n) {
  VaneProfile v;
  v.width_mm = j.member("width_mm").numbers(n, 0.0);
  v.width_confidence = j.member("width_confidence").numbers(n, 0, 1);
  v.barb_angle_deg = j.member("barb_angle_deg").numbers(n, 0, 180);
  v.barb_angle_confidence = j.member("barb_angle_confidence").numbers(n, 0, 1);
  v.barb_spacing_mm = j.member("barb_spacing_mm").numbers(n, 0.0);
  v.barb_spacing_confidence = j.member("barb_spacing_confidence").numbers(n, 0, 1);
  // Optional: layouts written before the downy base was measured have none.
  if (const auto a = j.find("afterfeather_to_t")) v.afterfeather_to_t = a->number(0, 1);
  // Optional: layouts written before open vanes were measured have none.
  if (const auto o = j.find("open_share")) v.open_share = o->number(0, 1);
  // Optional: only a shingled row's feathers have hidden stations.
  if (const auto h = j.find("width_hidden")) v.width_hidden = h->numbers(n, 0, 1);
  return v;
}

glm::dvec3 read_rgb(const JsonReader& j) {
  const auto v = j.numbers(3, 0.0, kMaxAlbedoScale);
  return {v[0], v[1], v[2]};
}

FeatherLayout read_feather(const JsonReader& j) {
  FeatherLayout f;
  f.id = int(j.member("id").integer(1, 1 << 20));
  const JsonReader bbox = j.member("bbox_px");
  const auto bb = bbox.numbers(4, 0.0, 1e9);
  for (int i = 0; i < 4; ++i) {
    if (bb[std::size_t(i)] != std::floor(bb[std::size_t(i)])) bbox.fail("expected integers");
    f.bbox_px[i] = int(bb[std::size_t(i)]);
  }
  for (const JsonReader& p : j.member("outline_px").elements(0, 3)) f.outline_px.push_back(point(p));
  const JsonReader tr = j.member("transform");
  f.feather_from_image = matrix(tr.member("feather_from_image"));
  f.image_from_feather = matrix(tr.member("image_from_feather"));
  const JsonReader sh = j.member("shaft");
  std::vector<glm::dvec2> control;
  for (const JsonReader& p : sh.member("control_points_mm").elements(0, 4)) control.push_back(point(p));
  f.shaft_mm = BSpline2(std::move(control));
  f.length_mm = sh.member("length_mm").number(1e-9);
  f.shaft_width_mm = sh.member("width_mm").number(0.0);
  f.shaft_confidence = sh.member("confidence").number(0, 1);
  if (const auto seen = sh.find("seen_as_ridge")) f.shaft_seen = seen->number(0, 1);
  const JsonReader stations = j.member("stations_t");
  f.stations_t = stations.numbers(0, 0.0, 1.0);
  if (f.stations_t.empty()) stations.fail("expected at least one station");
  // The analysis writes a few dozen; layout -> params smooths along them in
  // O(n^2 log n), so a hand-made layout with very many would take minutes.
  if (f.stations_t.size() > kMaxLayoutStations)
    stations.fail("at most " + std::to_string(kMaxLayoutStations) + " stations (this has " +
                  std::to_string(f.stations_t.size()) + "); resample the layout more coarsely");
  for (std::size_t i = 1; i < f.stations_t.size(); ++i)
    if (!(f.stations_t[i] > f.stations_t[i - 1])) stations.fail("must increase");
  const JsonReader vanes = j.member("vanes");
  f.left = read_vane(vanes.member("left"), f.stations_t.size());
  f.right = read_vane(vanes.member("right"), f.stations_t.size());
  const JsonReader al = j.member("albedo");
  const JsonReader file = al.member("file");
  f.albedo.file = file.string();
  if (f.albedo.file.empty() || f.albedo.file.find('/') != std::string::npos)
    file.fail("expected a file name next to layout.json (no directories)");
  f.albedo.width_px = int(al.member("width_px").integer(1, 1 << 16));
  f.albedo.height_px = int(al.member("height_px").integer(1, 1 << 16));
  f.albedo.origin_mm = point(al.member("origin_mm"));
  f.albedo.mm_per_texel = al.member("mm_per_texel").number(1e-9);
  if (const auto scale = al.find("scale")) f.albedo.scale = scale->number(1.0, kMaxAlbedoScale);
  if (const auto c = al.find("shaft_rgb")) {
    // [r, g, b] for the whole shaft, or [[r, g, b], ...] from the base to the tip.
    if (!c->value().is_array() || c->value().empty()) c->fail("expected [r, g, b] or a list of them");
    if (c->value()[0].is_array()) {
      for (const JsonReader& k : c->elements(0, 1, kMaxShaftColours)) f.albedo.shaft_rgb.push_back(read_rgb(k));
    } else {
      f.albedo.shaft_rgb.push_back(read_rgb(*c));
    }
  }
  f.touches_border = j.member("touches_border").boolean();
  if (const auto row = j.find("shingled_row")) {
    f.row.region = int(row->member("region").integer(1, 1 << 20));
    f.row.feathers = int(row->member("feathers").integer(2, 1 << 20));
  }
  for (const JsonReader& w : j.member("warnings").elements()) f.warnings.push_back(w.string());
  return f;
}

}  // namespace

const char* to_string(ScaleSource s) {
  switch (s) {
    case ScaleSource::Given:
      return "given";
    case ScaleSource::Grid:
      return "grid";
    case ScaleSource::Default:
      return "default";
  }
  return "default";
}

double shaft_s_ness(const BSpline2& shaft) {
  constexpr int kSamples = 513;
  std::vector<glm::dvec2> pts(kSamples);
  double length = 0;
  for (int i = 0; i < kSamples; ++i) {
    pts[i] = shaft.eval(double(i) / (kSamples - 1));
    if (i > 0) length += glm::length(pts[i] - pts[i - 1]);
  }
  const glm::dvec2 chord = pts.back() - pts.front();
  if (!(length > 0) || !(glm::length(chord) > 0)) return 0.0;
  const glm::dvec2 e = chord / glm::length(chord), n(-e.y, e.x);
  // Least squares v = a + b u + c u^2 (u along the chord in units of its length,
  // v across it) from its normal equations.
  const double scale = glm::length(chord);
  double S[5] = {0, 0, 0, 0, 0}, T[3] = {0, 0, 0};
  std::vector<double> u(kSamples), v(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    u[i] = glm::dot(pts[i] - pts.front(), e) / scale;
    v[i] = glm::dot(pts[i] - pts.front(), n);
    double p = 1;
    for (int k = 0; k < 5; ++k) S[k] += p, p *= u[i];
    T[0] += v[i], T[1] += v[i] * u[i], T[2] += v[i] * u[i] * u[i];
  }
  const glm::dmat3 A(S[0], S[1], S[2], S[1], S[2], S[3], S[2], S[3], S[4]);
  const double det = glm::determinant(A);
  if (!(std::fabs(det) > 1e-12)) return 0.0;
  const glm::dvec3 coef = glm::inverse(A) * glm::dvec3(T[0], T[1], T[2]);
  double worst = 0;
  for (int i = 0; i < kSamples; ++i)
    worst = std::max(worst, std::fabs(v[i] - (coef[0] + coef[1] * u[i] + coef[2] * u[i] * u[i])));
  return worst / length;
}

std::string layout_to_json(const Layout& L) {
  ojson feathers = ojson::array();
  for (const FeatherLayout& f : L.feathers) {
    ojson outline = ojson::array();
    for (const auto& p : f.outline_px) outline.push_back(vec2(p));
    ojson cps = ojson::array();
    for (const auto& p : f.shaft_mm.control_points()) cps.push_back(vec2(p));
    feathers.push_back(ojson{{"id", f.id},
                             {"bbox_px", f.bbox_px},
                             {"outline_px", outline},
                             {"transform",
                              {{"feather_from_image", affine(f.feather_from_image)},
                               {"image_from_feather", affine(f.image_from_feather)}}},
                             {"shaft",
                              {{"control_points_mm", cps},
                               {"length_mm", f.length_mm},
                               {"width_mm", f.shaft_width_mm},
                               {"confidence", f.shaft_confidence},
                               {"seen_as_ridge", f.shaft_seen},
                               {"s_ness", shaft_s_ness(f.shaft_mm)}}},
                             {"stations_t", f.stations_t},
                             {"vanes", {{"left", profile(f.left)}, {"right", profile(f.right)}}},
                             {"albedo",
                              {{"file", f.albedo.file},
                               {"width_px", f.albedo.width_px},
                               {"height_px", f.albedo.height_px},
                               {"origin_mm", vec2(f.albedo.origin_mm)},
                               {"mm_per_texel", f.albedo.mm_per_texel}}},
                             {"touches_border", f.touches_border},
                             {"warnings", f.warnings}});
    if (f.row.feathers > 0)
      feathers.back()["shingled_row"] = {{"region", f.row.region}, {"feathers", f.row.feathers}};
    if (f.albedo.scale != 1.0) feathers.back()["albedo"]["scale"] = f.albedo.scale;  // only a feather paler than its paper
    const auto rgb = [](const glm::dvec3& c) { return ojson::array({c.x, c.y, c.z}); };
    if (f.albedo.shaft_rgb.size() == 1) {
      feathers.back()["albedo"]["shaft_rgb"] = rgb(f.albedo.shaft_rgb[0]);
    } else if (!f.albedo.shaft_rgb.empty()) {
      ojson list = ojson::array();
      for (const glm::dvec3& c : f.albedo.shaft_rgb) list.push_back(rgb(c));
      feathers.back()["albedo"]["shaft_rgb"] = std::move(list);
    }
  }
  ojson skipped = ojson::array();
  for (const SkippedRegion& s : L.skipped)
    skipped.push_back(
        ojson{{"id", s.id}, {"bbox_px", s.bbox_px}, {"reason", s.reason}, {"message", s.message}});
  const ojson doc = {{"format", kFormat},
                     {"version", kVersion},
                     {"image",
                      {{"file", L.source_image},
                       {"width_px", L.image_width},
                       {"height_px", L.image_height},
                       {"analysis_downscale", L.analysis_downscale},
                       {"background", L.background}}},
                     {"scale",
                      {{"mm_per_px", L.scale.mm_per_px},
                       {"source", to_string(L.scale.source)},
                       {"confidence", L.scale.confidence},
                       {"grid_period_px", L.scale.grid_period_px},
                       {"grid_mm", L.scale.grid_mm}}},
                     {"feathers", feathers},
                     {"skipped", skipped}};
  std::string out;
  dump(doc, 0, out);
  return out + "\n";
}

Layout parse_layout(const std::string& text, const std::string& source) {
  const json doc = parse_json(text, source);
  const JsonReader top(doc, source, "see docs/layout-format.md");
  const JsonReader format = top.member("format");
  if (format.string() != kFormat) format.fail(std::string("expected \"") + kFormat + "\"");
  top.member("version").integer(kVersion, kVersion);
  Layout L;
  const JsonReader im = top.member("image");
  L.source_image = im.member("file").string();
  L.image_width = int(im.member("width_px").integer(1, 1 << 20));
  L.image_height = int(im.member("height_px").integer(1, 1 << 20));
  L.analysis_downscale = im.member("analysis_downscale").number(1e-6, 1.0);
  const JsonReader background = im.member("background");
  L.background = background.string();
  if (L.background != "light" && L.background != "dark") background.fail("expected \"light\" or \"dark\"");
  const JsonReader sc = top.member("scale");
  L.scale.mm_per_px = sc.member("mm_per_px").number(1e-9, 1e6);
  const JsonReader source_of_scale = sc.member("source");
  const std::string src = source_of_scale.string();
  if (src == "given")
    L.scale.source = ScaleSource::Given;
  else if (src == "grid")
    L.scale.source = ScaleSource::Grid;
  else if (src == "default")
    L.scale.source = ScaleSource::Default;
  else
    source_of_scale.fail("expected \"given\", \"grid\" or \"default\"");
  L.scale.confidence = sc.member("confidence").number(0, 1);
  L.scale.grid_period_px = sc.member("grid_period_px").number(0);
  L.scale.grid_mm = sc.member("grid_mm").number(0);
  for (const JsonReader& f : top.member("feathers").elements(0, 1)) L.feathers.push_back(read_feather(f));
  // Optional: layouts written before regions could be skipped have none.
  if (const auto sk = top.find("skipped"))
    for (const JsonReader& r : sk->elements()) {
      SkippedRegion s;
      s.id = int(r.member("id").integer(1, 1 << 20));
      const auto bb = r.member("bbox_px").numbers(4, 0.0, 1e9);
      for (int k = 0; k < 4; ++k) s.bbox_px[k] = int(bb[std::size_t(k)]);
      const JsonReader reason = r.member("reason");
      s.reason = reason.string();
      if (s.reason != "touches_border" && s.reason != "unseparated" && s.reason != "split_row")
        reason.fail("expected \"touches_border\", \"unseparated\" or \"split_row\"");
      s.message = r.member("message").string();
      L.skipped.push_back(std::move(s));
    }
  return L;
}

Layout read_layout(const std::filesystem::path& path) {
  return parse_layout(read_json_text(path), path.string());
}

void write_layout(const std::filesystem::path& path, const Layout& layout) {
  write_file_atomic(path, layout_to_json(layout));
}

}  // namespace plumage
