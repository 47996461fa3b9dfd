// The `.fcurves` reader and writer (spec: docs/curve-format.md).
//
// The reader is a single pass over the text, one line at a time, with tokens as
// views into the text: no per-token allocation, numbers through std::from_chars.
// Every rule it enforces throws plumage::Error at the line and column of the
// offending token, so a person editing a file by hand is told where and what.
#include "plumage/common/curve_format.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <cmath>
#include <limits>
#include <system_error>
#include <utility>

#include "float_text.h"
#include "line_reader.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/text.h"
#include "plumage/common/stats.h"

namespace plumage {

namespace {

StatCounter files_read("Curve files/Files read");
StatCounter bytes_read("Curve files/Bytes parsed");
StatCounter curves_read("Curve files/Curves read");
StatCounter points_read("Curve files/Control points read");
StatCounter bytes_written("Curve files/Bytes formatted");

// ---------------------------------------------------------------- writing ---


constexpr double kNormalTolerance = 1e-3;  // accepted deviation of |n| from 1

using detail::append_float;
using detail::append_vec3;
using detail::append_int;
using detail::append_quoted;
using detail::printable_string;

}  // namespace

// The writer refuses what the reader would refuse, so every file it writes reads back.
void validate_feather(const Feather& f) {
  auto fail = [](const std::string& what) { throw Error("invalid feather: " + what); };
  if (f.units != "mm") fail("units are '" + f.units + "'; Plumage works in millimetres ('mm')");
  if (!printable_string(f.provenance.source))
    fail("provenance source contains a control character (newline, tab, ...)");
  if (!printable_string(f.albedo.texture))
    fail("albedo texture path contains a control character (newline, tab, ...)");
  if (invalid_utf8_at(f.provenance.source) != std::string_view::npos) fail("provenance source is not UTF-8 text");
  if (invalid_utf8_at(f.albedo.texture) != std::string_view::npos) fail("albedo texture path is not UTF-8 text");
  auto finite3 = [](const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!finite3(f.albedo.color) || f.albedo.color.x < 0 || f.albedo.color.y < 0 || f.albedo.color.z < 0)
    fail("albedo colour must be finite and non-negative");
  if (f.albedo.shaft.size() > kMaxShaftColours)
    fail("albedo shaft has " + std::to_string(f.albedo.shaft.size()) + " colours; at most " +
         std::to_string(kMaxShaftColours));
  for (const glm::vec3& c : f.albedo.shaft)
    if (!finite3(c) || c.x < 0 || c.y < 0 || c.z < 0) fail("albedo shaft colour must be finite and non-negative");
  if (!(f.albedo.scale >= 1 && f.albedo.scale <= kMaxAlbedoScale))
    fail("albedo scale must lie in [1, 8] (a texel times it is the albedo)");
  if (!(f.medulla.ratio >= 0 && f.medulla.ratio < 1))
    fail("medulla ratio must lie in [0, 1) (the core's radius over the fibre's)");
  if (!finite3(f.medulla.sigma_s) || !finite3(f.medulla.sigma_a) || f.medulla.sigma_s.x < 0 || f.medulla.sigma_s.y < 0 ||
      f.medulla.sigma_s.z < 0 || f.medulla.sigma_a.x < 0 || f.medulla.sigma_a.y < 0 || f.medulla.sigma_a.z < 0)
    fail("medulla coefficients must be finite and non-negative");
  if (!(f.down_cover > 0 && f.down_cover <= 1))
    fail("down cover must lie in (0, 1] (the share of a down barb's tube its fibres fill)");
  if (!f.albedo.texture.empty()) {
    const glm::vec2 a = f.albedo.rect_min, b = f.albedo.rect_max;
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y) ||
        !(a.x < b.x) || !(a.y < b.y))
      fail("albedo texture rectangle must be finite with min < max");
  }
  for (VaneSide s : {VaneSide::Left, VaneSide::Right}) {
    if (const auto bad = substructure_problem(f.substructure(s)))
      fail(std::string("substructure ") + to_string(s) + " " + bad->setting + ": " + bad->problem +
           " (docs/curve-format.md)");
  }
  std::size_t shafts = 0, index = 0;
  for (const Curve& c : f.curves) {
    const std::string which = "curve " + std::to_string(index++);
    if (c.kind == CurveKind::Shaft) {
      if (++shafts > 1) fail("more than one shaft");
      if (c.side != VaneSide::None) fail(which + ": the shaft must have side none");
      if (index != 1) fail(which + ": the shaft must be the first curve");
    } else if (c.side == VaneSide::None) {
      fail(which + ": a barb needs a side (left or right)");
    }
    if (!(c.root >= 0 && c.root <= 1)) fail(which + ": root must be in [0,1]");
    if (c.points.size() < 4) fail(which + ": a cubic B-spline needs at least 4 control points");
    for (const ControlPoint& p : c.points) {
      if (!finite3(p.p) || !finite3(p.n) || !std::isfinite(p.radius))
        fail(which + ": control point is not finite");
      if (p.radius < 0) fail(which + ": negative radius");
      const double len = glm::length(glm::dvec3(p.n));
      if (std::abs(len - 1.0) > kNormalTolerance) fail(which + ": normal is not unit length");
    }
  }
}

namespace {

// ---------------------------------------------------------------- reading ---

const char* const kPointFields = "x y z radius nx ny nz";

using detail::LineReader;
using detail::Token;

class Reader : LineReader {
 public:
  Reader(std::string_view text, const std::string& filename) : LineReader(text, filename) {}

  Feather parse();

 private:
  void parse_record(Feather& f);
  void parse_albedo(Feather& f);
  void parse_substructure(Feather& f);
  void parse_curve(Feather& f);
  void parse_point(ControlPoint& p);
  void parse_trailer();

  // Records seen (line numbers, 0 = not yet), to reject duplicates and check required ones.
  int shaft_colour_line_ = 0, scale_line_ = 0, medulla_line_ = 0, down_line_ = 0, units_line_ = 0, source_line_ = 0, seed_line_ = 0,
      color_line_ = 0, texture_line_ = 0, left_line_ = 0, right_line_ = 0, curves_line_ = 0, shaft_line_ = 0,
      last_curve_line_ = 0;
  std::uint64_t declared_curves_ = 0;
  bool in_curves_ = false;
};


void Reader::parse_albedo(Feather& f) {
  if (tok_.size() < 2) fail(end_column(), "albedo: expected 'color', 'texture', 'shaft' or 'scale'");
  const Token& kind = tok_[1];
  if (kind.text == "color") {
    if (color_line_)
      fail(tok_[0], "second 'albedo color' record (first on line " + std::to_string(color_line_) + ")");
    color_line_ = line_no_;
    expect_count(5, "albedo color R G B");
    for (int i = 0; i < 3; ++i) f.albedo.color[i] = nonneg_float(tok_[2 + i], "albedo colour");
  } else if (kind.text == "texture") {
    if (texture_line_)
      fail(tok_[0], "second 'albedo texture' record (first on line " + std::to_string(texture_line_) + ")");
    texture_line_ = line_no_;
    expect_count(7, "albedo texture \"FILE\" XMIN YMIN XMAX YMAX");
    f.albedo.texture = quoted(tok_[2], "albedo texture");
    if (f.albedo.texture.empty()) fail(tok_[2], "albedo texture: the file name is empty");
    f.albedo.rect_min = {finite_float(tok_[3], "albedo texture XMIN"),
                         finite_float(tok_[4], "albedo texture YMIN")};
    f.albedo.rect_max = {finite_float(tok_[5], "albedo texture XMAX"),
                         finite_float(tok_[6], "albedo texture YMAX")};
    if (!(f.albedo.rect_min.x < f.albedo.rect_max.x))
      fail(tok_[5], "albedo texture: XMAX must be greater than XMIN");
    if (!(f.albedo.rect_min.y < f.albedo.rect_max.y))
      fail(tok_[6], "albedo texture: YMAX must be greater than YMIN");
  } else if (kind.text == "shaft") {
    if (shaft_colour_line_)
      fail(tok_[0], "second 'albedo shaft' record (first on line " + std::to_string(shaft_colour_line_) + ")");
    shaft_colour_line_ = line_no_;
    // One colour, or one per station along the shaft from its root: R G B [R G B ...].
    const std::size_t given = tok_.size() - 2;
    if (given < 3) expect_count(5, "albedo shaft R G B [R G B ...]");
    if (given > 3 * kMaxShaftColours)
      fail(tok_[2 + 3 * kMaxShaftColours],
           "'albedo shaft' holds more than " + std::to_string(kMaxShaftColours) + " colours");
    if (given % 3 != 0)
      fail(end_column(), "'albedo shaft' record is incomplete: expected whole R G B triples (" +
                             std::to_string(given) + " numbers given)");
    f.albedo.shaft.clear();
    for (std::size_t k = 0; k < given / 3; ++k) {
      glm::vec3 c;
      for (std::size_t i = 0; i < 3; ++i) c[int(i)] = nonneg_float(tok_[2 + 3 * k + i], "albedo shaft colour");
      f.albedo.shaft.push_back(c);
    }
  } else if (kind.text == "scale") {
    if (scale_line_)
      fail(tok_[0], "second 'albedo scale' record (first on line " + std::to_string(scale_line_) + ")");
    scale_line_ = line_no_;
    expect_count(3, "albedo scale S");
    f.albedo.scale = ranged_float(tok_[2], "albedo scale", 1.0f, float(kMaxAlbedoScale), "[1, 8]");
  } else {
    fail(kind, "albedo: expected 'color', 'texture', 'shaft' or 'scale', found '" + std::string(kind.text) + "'");
  }
}

void Reader::parse_substructure(Feather& f) {
  if (tok_.size() < 2) fail(end_column(), "substructure: expected a vane side, 'left' or 'right'");
  const Token& side = tok_[1];
  int* seen = nullptr;
  SubstructureParams p;
  if (side.text == "left")
    seen = &left_line_;
  else if (side.text == "right")
    seen = &right_line_;
  else
    fail(side, "substructure: expected 'left' or 'right', found '" + std::string(side.text) + "'");
  if (*seen)
    fail(tok_[0], "second 'substructure " + std::string(side.text) + "' record (first on line " +
                      std::to_string(*seen) + ")");
  *seen = line_no_;

  static constexpr const char* kKeys[] = {"barbules", "ramus_radius",    "barbule_radius", "elevation",
                                          "azimuth",  "hooked_fraction", "ribbon_width"};
  constexpr int kNumKeys = 7;
  int key_col[kNumKeys] = {}, value_col[kNumKeys] = {};
  for (std::size_t i = 2; i < tok_.size(); i += 2) {
    const Token& key = tok_[i];
    int k = 0;
    while (k < kNumKeys && key.text != kKeys[k]) ++k;
    if (k == kNumKeys)
      fail(key, "substructure: unknown key '" + std::string(key.text) +
                    "' (known: barbules ramus_radius barbule_radius elevation azimuth hooked_fraction "
                    "ribbon_width)");
    if (key_col[k]) fail(key, "substructure: key '" + std::string(key.text) + "' given twice");
    key_col[k] = key.column;
    if (i + 1 >= tok_.size())
      fail(end_column(), "substructure: expected a value after '" + std::string(key.text) + "'");
    const Token& v = tok_[i + 1];
    value_col[k] = v.column;
    switch (k) {
      case 0: {
        const std::uint64_t n = unsigned_int(v, "barbules");
        if (n > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) fail(v, "barbules: too large");
        p.barbules_per_side = static_cast<int>(n);
        break;
      }
      case 1:
        p.ramus_radius = nonneg_float(v, "ramus_radius");
        break;
      case 2:
        p.barbule_radius = nonneg_float(v, "barbule_radius");
        break;
      case 3:
        p.elevation_deg = finite_float(v, "elevation");
        break;
      case 4:
        p.azimuth_deg = finite_float(v, "azimuth");
        break;
      case 5:
        p.hooked_fraction = finite_float(v, "hooked_fraction");
        break;
      case 6:
        p.ribbon_width = nonneg_float(v, "ribbon_width");
        break;
    }
  }
  for (int k = 0; k < kNumKeys; ++k)
    if (!key_col[k])
      fail(end_column(),
           "substructure " + std::string(side.text) + ": missing required key '" + kKeys[k] + "'");
  // Ranges: the one check all stages share, reported at the value's key.
  if (const auto bad = substructure_problem(p)) {
    int k = 0;
    while (k < kNumKeys && bad->setting != kKeys[k]) ++k;
    fail(k < kNumKeys ? value_col[k] : value_col[0], "substructure " + std::string(side.text) + " " + bad->setting +
                                                     ": " + bad->problem);
  }
  f.substructure(side.text == "left" ? VaneSide::Left : VaneSide::Right) = p;
}

void Reader::parse_record(Feather& f) {
  const Token& key = tok_[0];
  const std::string_view k = key.text;
  auto once = [&](int& seen) {
    if (seen)
      fail(key, "second '" + std::string(k) + "' record (first on line " + std::to_string(seen) + ")");
    seen = line_no_;
  };
  if (k == "curve") return parse_curve(f);
  if (k == "fcurves")
    fail(key, "second 'fcurves' header: a file holds one feather (was a file pasted into another?)");
  const char c0 = k.front();
  if ((c0 >= '0' && c0 <= '9') || c0 == '-' || c0 == '.') {
    if (in_curves_)
      fail(key, "unexpected numbers: the curve on line " + std::to_string(last_curve_line_) +
                    " has more point lines than its NPOINTS says");
    fail(key, "unexpected numbers outside a curve: control points follow a 'curve' record");
  }
  const bool header =
      k == "units" || k == "source" || k == "seed" || k == "albedo" || k == "medulla" || k == "down" ||
      k == "substructure" ||
      k == "curves";
  if (!header)
    fail(key, "unknown record '" + std::string(k) +
                  "' (expected units, source, seed, albedo, medulla, down, substructure, curves, curve or end)");
  if (in_curves_)
    fail(key, "header record '" + std::string(k) + "' after the first curve: move it above the curves");
  if (k == "units") {
    once(units_line_);
    expect_count(2, "units mm");
    if (tok_[1].text != "mm")
      fail(tok_[1], "units: only 'mm' is supported (Plumage works in millimetres), found '" +
                        std::string(tok_[1].text) + "'");
    f.units = "mm";
  } else if (k == "source") {
    once(source_line_);
    expect_count(2, "source \"TEXT\"");
    f.provenance.source = quoted(tok_[1], "source");
  } else if (k == "seed") {
    once(seed_line_);
    expect_count(2, "seed N");
    f.provenance.seed = unsigned_int(tok_[1], "seed");
  } else if (k == "albedo") {
    parse_albedo(f);
  } else if (k == "down") {
    once(down_line_);
    expect_count(3, "down cover C");
    if (tok_[1].text != "cover") fail(tok_[1], "down: expected 'cover', found '" + std::string(tok_[1].text) + "'");
    f.down_cover = ranged_float(tok_[2], "down cover", std::nextafter(0.0f, 1.0f), 1.0f, "(0, 1]");
  } else if (k == "medulla") {
    once(medulla_line_);
    expect_count(8, "medulla RATIO SIGMA_S_R SIGMA_S_G SIGMA_S_B SIGMA_A_R SIGMA_A_G SIGMA_A_B");
    f.medulla.ratio = ranged_float(tok_[1], "medulla RATIO", 0.0f, std::nextafter(1.0f, 0.0f), "[0, 1)");
    for (int i = 0; i < 3; ++i) f.medulla.sigma_s[i] = nonneg_float(tok_[2 + i], "medulla SIGMA_S");
    for (int i = 0; i < 3; ++i) f.medulla.sigma_a[i] = nonneg_float(tok_[5 + i], "medulla SIGMA_A");
  } else if (k == "substructure") {
    parse_substructure(f);
  } else {  // curves
    once(curves_line_);
    expect_count(2, "curves N");
    declared_curves_ = unsigned_int(tok_[1], "curves");
    // A count that lies must not make us allocate: each curve takes at least five lines of text.
    const std::uint64_t room = (text_.size() - std::min(pos_, text_.size())) / 40 + 1;
    f.curves.reserve(static_cast<std::size_t>(std::min(declared_curves_, room)));
  }
}

void Reader::parse_point(ControlPoint& p) {
  if (tok_.size() != 7) {
    if (tok_.size() < 7)
      fail(end_column(), "control point: expected 7 numbers (" + std::string(kPointFields) + "), found " +
                             std::to_string(tok_.size()));
    fail(tok_[7], "control point: expected 7 numbers (" + std::string(kPointFields) + "), found " +
                      std::to_string(tok_.size()));
  }
  p.p.x = finite_float(tok_[0], "x");
  p.p.y = finite_float(tok_[1], "y");
  p.p.z = finite_float(tok_[2], "z");
  p.radius = finite_float(tok_[3], "radius");
  if (p.radius < 0) fail(tok_[3], "radius: must not be negative, found '" + std::string(tok_[3].text) + "'");
  p.n.x = finite_float(tok_[4], "nx");
  p.n.y = finite_float(tok_[5], "ny");
  p.n.z = finite_float(tok_[6], "nz");
  const glm::dvec3 n(p.n);
  const double len = std::sqrt(glm::dot(n, n));
  if (!(len > 1e-6))
    fail(tok_[4], "normal: zero length, expected a unit vector (the vane's dorsal direction)");
  // Hand-edited normals need not be exactly unit; within tolerance they are kept
  // bit-exact so written files round-trip.
  if (std::abs(len - 1.0) > kNormalTolerance) p.n = glm::vec3(n / len);
}

void Reader::parse_curve(Feather& f) {
  in_curves_ = true;
  if (!units_line_) fail(tok_[0], "missing 'units mm' record before the first curve");
  if (!curves_line_) fail(tok_[0], "missing 'curves N' record before the first curve");
  const char* form = "curve shaft|barb|down none|left|right bspline NPOINTS root F";
  expect_count(7, form);
  if (f.curves.size() >= declared_curves_)
    fail(tok_[0], "more curves than the 'curves " + std::to_string(declared_curves_) + "' record on line " +
                      std::to_string(curves_line_) + " declares");
  Curve c;
  if (tok_[1].text == "shaft")
    c.kind = CurveKind::Shaft;
  else if (tok_[1].text == "barb")
    c.kind = CurveKind::Barb;
  else if (tok_[1].text == "down")
    c.kind = CurveKind::Down;
  else
    fail(tok_[1], "curve kind: expected 'shaft', 'barb' or 'down', found '" + std::string(tok_[1].text) + "'");
  if (tok_[2].text == "none")
    c.side = VaneSide::None;
  else if (tok_[2].text == "left")
    c.side = VaneSide::Left;
  else if (tok_[2].text == "right")
    c.side = VaneSide::Right;
  else
    fail(tok_[2], "vane side: expected 'none', 'left' or 'right', found '" + std::string(tok_[2].text) + "'");
  if (c.kind == CurveKind::Shaft) {
    if (c.side != VaneSide::None) fail(tok_[2], "the shaft belongs to no vane: its side must be 'none'");
    if (shaft_line_) fail(tok_[1], "second shaft (the first is on line " + std::to_string(shaft_line_) + ")");
    if (!f.curves.empty()) fail(tok_[1], "the shaft must be the first curve");
    shaft_line_ = line_no_;
  } else if (c.side == VaneSide::None) {
    fail(tok_[2], std::string(c.kind == CurveKind::Down ? "a down barb" : "a barb") +
                      " belongs to a vane: its side must be 'left' or 'right'");
  }
  if (tok_[3].text != "bspline")
    fail(tok_[3], "basis: only 'bspline' (uniform cubic B-spline) is supported, found '" +
                      std::string(tok_[3].text) + "'");
  const std::uint64_t npoints = unsigned_int(tok_[4], "NPOINTS");
  if (npoints < 4)
    fail(tok_[4], "a cubic B-spline needs at least 4 control points, found " + std::string(tok_[4].text));
  if (tok_[5].text != "root") fail(tok_[5], "expected 'root', found '" + std::string(tok_[5].text) + "'");
  c.root = ranged_float(tok_[6], "root", 0, 1, "[0, 1] (a fraction of the shaft length)");

  const int curve_line = line_no_;
  last_curve_line_ = line_no_;
  // Never trust the count for allocation: a point line is at least 14 bytes.
  const std::uint64_t room = (text_.size() - std::min(pos_, text_.size())) / 14 + 1;
  c.points.resize(static_cast<std::size_t>(std::min(npoints, room)));
  for (std::uint64_t i = 0; i < npoints; ++i) {
    do {
      if (!next_line())
        fail(end_column(), "file ends inside the curve on line " + std::to_string(curve_line) +
                               ": expected point " + std::to_string(i + 1) + " of " +
                               std::to_string(npoints) + " (truncated file?)");
    } while (tok_.empty());
    if (tok_[0].text == "curve" || tok_[0].text == "end")
      fail(tok_[0], "expected point " + std::to_string(i + 1) + " of " + std::to_string(npoints) +
                        " of the curve on line " + std::to_string(curve_line) + ", found '" +
                        std::string(tok_[0].text) + "' (NPOINTS says more points than there are)");
    if (i >= c.points.size()) c.points.emplace_back();
    parse_point(c.points[static_cast<std::size_t>(i)]);
  }
  f.curves.push_back(std::move(c));
}

void Reader::parse_trailer() {
  while (next_line())
    if (!tok_.empty()) fail(tok_[0], "text after 'end': a file holds one feather and stops at 'end'");
}

Feather Reader::parse() {
  Feather f;
  read_header("fcurves", kFcurvesVersion, "a .fcurves file");
  for (;;) {
    if (!next_line()) fail(end_column(), "missing 'end' at the end of the file (truncated file?)");
    if (tok_.empty()) continue;
    if (tok_[0].text == "end") {
      expect_count(1, "end");
      if (!units_line_) fail(tok_[0], "missing 'units mm' record");
      if (!curves_line_) fail(tok_[0], "missing 'curves N' record");
      if (f.curves.size() != declared_curves_)
        fail(tok_[0], "the file has " + std::to_string(f.curves.size()) +
                          " curves but the 'curves' record on line " + std::to_string(curves_line_) +
                          " declares " + std::to_string(declared_curves_) + " (truncated or edited file?)");
      break;
    }
    if (tok_[0].text.front() == '"') fail(tok_[0], "expected a record name, found a string");
    parse_record(f);
  }
  parse_trailer();
  return f;
}

}  // namespace

std::string format_fcurves(const Feather& f) {
  validate_feather(f);
  std::string out;
  out.reserve(256 + f.num_control_points() * 64 + f.curves.size() * 48);
  out += "fcurves ";
  append_int(out, kFcurvesVersion);
  out += "\nunits mm\n";
  if (!f.provenance.source.empty()) {
    out += "source ";
    append_quoted(out, f.provenance.source);
    out += '\n';
  }
  if (f.provenance.seed) {
    out += "seed ";
    append_int(out, *f.provenance.seed);
    out += '\n';
  }
  out += "albedo color ";
  append_vec3(out, f.albedo.color);
  out += '\n';
  if (!f.albedo.texture.empty()) {
    out += "albedo texture ";
    append_quoted(out, f.albedo.texture);
    for (float v : {f.albedo.rect_min.x, f.albedo.rect_min.y, f.albedo.rect_max.x, f.albedo.rect_max.y}) {
      out += ' ';
      append_float(out, v);
    }
    out += '\n';
  }
  if (!f.albedo.shaft.empty()) {
    out += "albedo shaft";
    for (const glm::vec3& c : f.albedo.shaft) {
      out += ' ';
      append_vec3(out, c);
    }
    out += '\n';
  }
  if (f.albedo.scale != 1.0f) {
    out += "albedo scale ";
    append_float(out, f.albedo.scale);
    out += '\n';
  }
  if (f.medulla.ratio > 0) {
    out += "medulla ";
    append_float(out, f.medulla.ratio);
    out += ' ';
    append_vec3(out, f.medulla.sigma_s);
    out += ' ';
    append_vec3(out, f.medulla.sigma_a);
    out += '\n';
  }
  if (f.down_cover != 1.0f) {
    out += "down cover ";
    append_float(out, f.down_cover);
    out += '\n';
  }
  for (VaneSide s : {VaneSide::Left, VaneSide::Right}) {
    const SubstructureParams& p = f.substructure(s);
    out += "substructure ";
    out += to_string(s);
    out += " barbules ";
    append_int(out, p.barbules_per_side);
    const std::pair<const char*, float> fields[] = {
        {" ramus_radius ", p.ramus_radius}, {" barbule_radius ", p.barbule_radius},
        {" elevation ", p.elevation_deg},   {" azimuth ", p.azimuth_deg},
        {" hooked_fraction ", p.hooked_fraction}, {" ribbon_width ", p.ribbon_width}};
    for (const auto& [key, value] : fields) {
      out += key;
      append_float(out, value);
    }
    out += '\n';
  }
  out += "curves ";
  append_int(out, f.curves.size());
  out += '\n';
  for (const Curve& c : f.curves) {
    out += "curve ";
    out += to_string(c.kind);
    out += ' ';
    out += to_string(c.side);
    out += " bspline ";
    append_int(out, c.points.size());
    out += " root ";
    append_float(out, c.root);
    out += '\n';
    for (const ControlPoint& p : c.points) {
      append_vec3(out, p.p);
      out += ' ';
      append_float(out, p.radius);
      out += ' ';
      append_vec3(out, p.n);
      out += '\n';
    }
  }
  out += "end\n";
  bytes_written += static_cast<std::int64_t>(out.size());
  return out;
}

void write_fcurves(const std::filesystem::path& path, const Feather& feather) {
  write_file_atomic(path, format_fcurves(feather));
}

void write_fcurves(FileBatch& batch, const std::filesystem::path& path, const Feather& feather) {
  batch.stage_text(path, format_fcurves(feather));
}

Feather parse_fcurves(std::string_view text, const std::string& filename) {
  Feather f = Reader(text, filename).parse();
  ++files_read;
  bytes_read += static_cast<std::int64_t>(text.size());
  curves_read += static_cast<std::int64_t>(f.curves.size());
  points_read += static_cast<std::int64_t>(f.num_control_points());
  return f;
}

Feather read_fcurves(const std::filesystem::path& path) {
  // Its first 4 KiB are judged before the rest is read: a 900 MB file of zeros
  // named .fcurves is refused at once, not after reading it whole. Strings read
  // from a .fcurves reach JSON, XML, Python and pbrt writers: its text is UTF-8.
  if (check_input_file(path, "a curve file") > kJudgedBytes) check_text_head(read_file_head(path), path.string());
  return parse_fcurves(read_file(path), path.string());
}

}  // namespace plumage
