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
  return {{"width_mm", v.width_mm},
          {"width_confidence", v.width_confidence},
          {"barb_angle_deg", v.barb_angle_deg},
          {"barb_angle_confidence", v.barb_angle_confidence},
          {"barb_spacing_mm", v.barb_spacing_mm},
          {"barb_spacing_confidence", v.barb_spacing_confidence},
          {"afterfeather_to_t", v.afterfeather_to_t}};
}

// --- strict reading: every access names its JSON path -----------------------

struct Reader {
  const std::string& source;
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw Error(Location{source},
                (path.empty() ? "/" : path) + ": " + what + " (see docs/layout-format.md)");
  }
  const json& member(const json& obj, const std::string& path, const char* key) const {
    if (!obj.is_object()) fail(path, "expected an object");
    auto it = obj.find(key);
    if (it == obj.end()) fail(path, std::string("missing key \"") + key + "\"");
    return *it;
  }
  // "[lo, hi]", ">= lo" or "<= hi", the ends as a person reads them.
  static std::string allowed(double lo, double hi) {
    std::string text = std::isinf(hi) ? ">= " : std::isinf(lo) ? "<= " : "[";
    if (!std::isinf(lo)) text += num(lo);
    if (!std::isinf(lo) && !std::isinf(hi)) text += ", ";
    if (!std::isinf(hi)) text += num(hi);
    if (!std::isinf(lo) && !std::isinf(hi)) text += "]";
    return text;
  }
  double number(const json& j, const std::string& path, double lo = -INFINITY,
                double hi = INFINITY) const {
    if (!j.is_number()) fail(path, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi) fail(path, "value " + num(v) + " is out of range; allowed " + allowed(lo, hi));
    return v;
  }
  int integer(const json& j, const std::string& path, int lo, int hi) const {
    if (!j.is_number_integer()) fail(path, "expected an integer");
    const auto v = j.get<long long>();
    if (v < lo || v > hi) fail(path, "value " + std::to_string(v) + " is out of range; allowed integers " + allowed(lo, hi));
    return int(v);
  }
  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string");
    return j.get<std::string>();
  }
  bool boolean(const json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, "expected true or false");
    return j.get<bool>();
  }
  std::vector<double> numbers(const json& j, const std::string& path, std::size_t n,
                              double lo = -INFINITY, double hi = INFINITY) const {
    if (!j.is_array()) fail(path, "expected an array of numbers");
    if (n != 0 && j.size() != n)
      fail(path, "expected " + std::to_string(n) + " values, got " + std::to_string(j.size()));
    std::vector<double> out;
    for (std::size_t i = 0; i < j.size(); ++i)
      out.push_back(number(j[i], path + "/" + std::to_string(i), lo, hi));
    return out;
  }
  glm::dvec2 point(const json& j, const std::string& path) const {
    const auto v = numbers(j, path, 2);
    return {v[0], v[1]};
  }
  std::vector<glm::dvec2> points(const json& j, const std::string& path, std::size_t min_n) const {
    if (!j.is_array() || j.size() < min_n)
      fail(path, "expected an array of at least " + std::to_string(min_n) + " [x, y] points");
    std::vector<glm::dvec2> out;
    for (std::size_t i = 0; i < j.size(); ++i)
      out.push_back(point(j[i], path + "/" + std::to_string(i)));
    return out;
  }
  glm::dmat3x2 matrix(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 2) fail(path, "expected a 2x3 matrix [[a,b,c],[d,e,f]]");
    glm::dmat3x2 A;
    for (int r = 0; r < 2; ++r) {
      const auto row = numbers(j[r], path + "/" + std::to_string(r), 3);
      for (int c = 0; c < 3; ++c) A[c][r] = row[c];
    }
    const double det = A[0][0] * A[1][1] - A[1][0] * A[0][1];
    if (!(std::fabs(det) > 1e-12)) fail(path, "matrix is singular");
    return A;
  }

  VaneProfile vane(const json& j, const std::string& path, std::size_t n) const {
    VaneProfile v;
    v.width_mm = numbers(member(j, path, "width_mm"), path + "/width_mm", n, 0.0);
    v.width_confidence =
        numbers(member(j, path, "width_confidence"), path + "/width_confidence", n, 0, 1);
    v.barb_angle_deg =
        numbers(member(j, path, "barb_angle_deg"), path + "/barb_angle_deg", n, 0, 180);
    v.barb_angle_confidence =
        numbers(member(j, path, "barb_angle_confidence"), path + "/barb_angle_confidence", n, 0, 1);
    v.barb_spacing_mm =
        numbers(member(j, path, "barb_spacing_mm"), path + "/barb_spacing_mm", n, 0.0);
    v.barb_spacing_confidence = numbers(member(j, path, "barb_spacing_confidence"),
                                        path + "/barb_spacing_confidence", n, 0, 1);
    // Optional: layouts written before the downy base was measured have none.
    if (j.contains("afterfeather_to_t"))
      v.afterfeather_to_t = number(j["afterfeather_to_t"], path + "/afterfeather_to_t", 0, 1);
    return v;
  }

  FeatherLayout feather(const json& j, const std::string& p) const {
    FeatherLayout f;
    f.id = integer(member(j, p, "id"), p + "/id", 1, 1 << 20);
    const auto bb = numbers(member(j, p, "bbox_px"), p + "/bbox_px", 4, 0.0, 1e9);
    for (int i = 0; i < 4; ++i) {
      if (bb[i] != std::floor(bb[i])) fail(p + "/bbox_px", "expected integers");
      f.bbox_px[i] = int(bb[i]);
    }
    f.outline_px = points(member(j, p, "outline_px"), p + "/outline_px", 3);
    const json& tr = member(j, p, "transform");
    f.feather_from_image = matrix(member(tr, p + "/transform", "feather_from_image"),
                                  p + "/transform/feather_from_image");
    f.image_from_feather = matrix(member(tr, p + "/transform", "image_from_feather"),
                                  p + "/transform/image_from_feather");
    const json& sh = member(j, p, "shaft");
    f.shaft_mm = BSpline2(
        points(member(sh, p + "/shaft", "control_points_mm"), p + "/shaft/control_points_mm", 4));
    f.length_mm = number(member(sh, p + "/shaft", "length_mm"), p + "/shaft/length_mm", 1e-9);
    f.shaft_width_mm = number(member(sh, p + "/shaft", "width_mm"), p + "/shaft/width_mm", 0.0);
    f.shaft_confidence =
        number(member(sh, p + "/shaft", "confidence"), p + "/shaft/confidence", 0, 1);
    if (sh.contains("seen_as_ridge"))
      f.shaft_seen = number(sh["seen_as_ridge"], p + "/shaft/seen_as_ridge", 0, 1);
    f.stations_t = numbers(member(j, p, "stations_t"), p + "/stations_t", 0, 0.0, 1.0);
    if (f.stations_t.empty()) fail(p + "/stations_t", "expected at least one station");
    // The analysis writes a few dozen; layout -> params smooths along them in
    // O(n^2 log n), so a hand-made layout with very many would take minutes.
    if (f.stations_t.size() > kMaxLayoutStations)
      fail(p + "/stations_t", "at most " + std::to_string(kMaxLayoutStations) + " stations (this has " +
                                  std::to_string(f.stations_t.size()) + "); resample the layout more coarsely");
    for (std::size_t i = 1; i < f.stations_t.size(); ++i)
      if (!(f.stations_t[i] > f.stations_t[i - 1])) fail(p + "/stations_t", "must increase");
    const json& vanes = member(j, p, "vanes");
    f.left = vane(member(vanes, p + "/vanes", "left"), p + "/vanes/left", f.stations_t.size());
    f.right = vane(member(vanes, p + "/vanes", "right"), p + "/vanes/right", f.stations_t.size());
    const json& al = member(j, p, "albedo");
    const std::string ap = p + "/albedo";
    f.albedo.file = string(member(al, ap, "file"), ap + "/file");
    if (f.albedo.file.empty() || f.albedo.file.find('/') != std::string::npos)
      fail(ap + "/file", "expected a file name next to layout.json (no directories)");
    f.albedo.width_px = integer(member(al, ap, "width_px"), ap + "/width_px", 1, 1 << 16);
    f.albedo.height_px = integer(member(al, ap, "height_px"), ap + "/height_px", 1, 1 << 16);
    f.albedo.origin_mm = point(member(al, ap, "origin_mm"), ap + "/origin_mm");
    f.albedo.mm_per_texel = number(member(al, ap, "mm_per_texel"), ap + "/mm_per_texel", 1e-9);
    if (al.contains("scale")) {
      f.albedo.scale = number(al.at("scale"), ap + "/scale", 1.0, kMaxAlbedoScale);
    }
    if (al.contains("shaft_rgb")) {
      // [r, g, b] for the whole shaft, or [[r, g, b], ...] from the base to the tip.
      const json& c = al.at("shaft_rgb");
      const std::string cp = ap + "/shaft_rgb";
      const auto colour = [&](const json& v, const std::string& vp) {
        if (!v.is_array() || v.size() != 3) fail(vp, "expected [r, g, b]");
        glm::dvec3 rgb;
        for (int i = 0; i < 3; ++i) rgb[i] = number(v[std::size_t(i)], vp + "/" + std::to_string(i), 0.0, kMaxAlbedoScale);
        return rgb;
      };
      if (!c.is_array() || c.empty()) fail(cp, "expected [r, g, b] or a list of them");
      if (c[0].is_array()) {
        if (c.size() > kMaxShaftColours)
          fail(cp, "more than " + std::to_string(kMaxShaftColours) + " colours");
        for (std::size_t k = 0; k < c.size(); ++k) f.albedo.shaft_rgb.push_back(colour(c[k], cp + "/" + std::to_string(k)));
      } else {
        f.albedo.shaft_rgb.push_back(colour(c, cp));
      }
    }
    f.touches_border = boolean(member(j, p, "touches_border"), p + "/touches_border");
    const json& w = member(j, p, "warnings");
    if (!w.is_array()) fail(p + "/warnings", "expected an array of strings");
    for (std::size_t i = 0; i < w.size(); ++i)
      f.warnings.push_back(string(w[i], p + "/warnings/" + std::to_string(i)));
    return f;
  }
};

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
  const Reader r{source};
  if (r.string(r.member(doc, "", "format"), "/format") != kFormat)
    r.fail("/format", std::string("expected \"") + kFormat + "\"");
  r.integer(r.member(doc, "", "version"), "/version", kVersion, kVersion);
  Layout L;
  const json& im = r.member(doc, "", "image");
  L.source_image = r.string(r.member(im, "/image", "file"), "/image/file");
  L.image_width = r.integer(r.member(im, "/image", "width_px"), "/image/width_px", 1, 1 << 20);
  L.image_height = r.integer(r.member(im, "/image", "height_px"), "/image/height_px", 1, 1 << 20);
  L.analysis_downscale = r.number(r.member(im, "/image", "analysis_downscale"),
                                  "/image/analysis_downscale", 1e-6, 1.0);
  L.background = r.string(r.member(im, "/image", "background"), "/image/background");
  if (L.background != "light" && L.background != "dark")
    r.fail("/image/background", "expected \"light\" or \"dark\"");
  const json& sc = r.member(doc, "", "scale");
  L.scale.mm_per_px = r.number(r.member(sc, "/scale", "mm_per_px"), "/scale/mm_per_px", 1e-9, 1e6);
  const std::string src = r.string(r.member(sc, "/scale", "source"), "/scale/source");
  if (src == "given")
    L.scale.source = ScaleSource::Given;
  else if (src == "grid")
    L.scale.source = ScaleSource::Grid;
  else if (src == "default")
    L.scale.source = ScaleSource::Default;
  else
    r.fail("/scale/source", "expected \"given\", \"grid\" or \"default\"");
  L.scale.confidence = r.number(r.member(sc, "/scale", "confidence"), "/scale/confidence", 0, 1);
  L.scale.grid_period_px =
      r.number(r.member(sc, "/scale", "grid_period_px"), "/scale/grid_period_px", 0);
  L.scale.grid_mm = r.number(r.member(sc, "/scale", "grid_mm"), "/scale/grid_mm", 0);
  const json& fs = r.member(doc, "", "feathers");
  if (!fs.is_array() || fs.empty()) r.fail("/feathers", "expected a non-empty array of feathers");
  for (std::size_t i = 0; i < fs.size(); ++i)
    L.feathers.push_back(r.feather(fs[i], "/feathers/" + std::to_string(i)));
  // Optional: layouts written before regions could be skipped have none.
  if (doc.contains("skipped")) {
    const json& sk = doc["skipped"];
    if (!sk.is_array()) r.fail("/skipped", "expected an array of skipped regions");
    for (std::size_t i = 0; i < sk.size(); ++i) {
      const std::string p = "/skipped/" + std::to_string(i);
      SkippedRegion s;
      s.id = r.integer(r.member(sk[i], p, "id"), p + "/id", 1, 1 << 20);
      const auto bb = r.numbers(r.member(sk[i], p, "bbox_px"), p + "/bbox_px", 4, 0.0, 1e9);
      for (int k = 0; k < 4; ++k) s.bbox_px[k] = int(bb[k]);
      s.reason = r.string(r.member(sk[i], p, "reason"), p + "/reason");
      if (s.reason != "touches_border" && s.reason != "unseparated")
        r.fail(p + "/reason", "expected \"touches_border\" or \"unseparated\"");
      s.message = r.string(r.member(sk[i], p, "message"), p + "/message");
      L.skipped.push_back(std::move(s));
    }
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
