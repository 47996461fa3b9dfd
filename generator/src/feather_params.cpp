#include "plumage/generator/feather_params.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/json_file.h"
#include "plumage/common/json_reader.h"
#include "plumage/common/number_text.h"

namespace plumage {
using nlohmann::json;

int FeatherParams::barb_count(VaneSide s) const {
  const VaneParams& v = vane(s);
  if (v.barb_density > 0) return std::max(2, int(std::lround(v.barb_density * vane_length())));
  return v.barbs;
}

FeatherParams default_feather_params() {
  FeatherParams p;
  p.name = "default";
  const Profile width({{0.0, 6.0}, {0.25, 14.0}, {0.7, 12.0}, {0.93, 6.0}, {1.0, 0.0}});
  const Profile angle({{0.0, 60.0}, {1.0, 35.0}});
  for (VaneParams* v : {&p.left, &p.right}) {
    v->width = width;
    v->angle_deg = angle;
    v->substructure = SubstructureParams{40, 0.03f, 0.006f, 45.0f, 10.0f, 0.3f, 0.35f};
  }
  return p;
}

// ---------------------------------------------------------------------------
// Validation.
namespace {

class Checker {
 public:
  explicit Checker(const std::string& source) : source_(source) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw Error(Location{source_}, key + ": " + what);
  }
  void range(const std::string& key, double v, double lo, double hi, const std::string& unit = "") const {
    if (!(v >= lo && v <= hi))
      fail(key, "value " + num(v) + " is out of range; allowed [" + num(lo) + ", " + num(hi) + "]" +
                    (unit.empty() ? "" : " " + unit));
  }
  void range(const std::string& key, int v, int lo, int hi) const {
    if (v < lo || v > hi)
      fail(key, "value " + std::to_string(v) + " is out of range; allowed integers [" + std::to_string(lo) +
                    ", " + std::to_string(hi) + "]");
  }
  void profile(const std::string& key, const Profile& p, double lo, double hi, const std::string& unit) const {
    const auto& k = p.knots();
    if (k.size() < 2) fail(key, "needs at least 2 knots [position, value]; got " + std::to_string(k.size()));
    if (k.front().x != 0.0 || k.back().x != 1.0)
      fail(key, "knot positions must start at 0 (end of calamus) and end at 1 (tip); got " + num(k.front().x) +
                    " ... " + num(k.back().x));
    for (std::size_t i = 0; i < k.size(); ++i) {
      const std::string at = key + "[" + std::to_string(i) + "]";
      if (!std::isfinite(k[i].x) || !std::isfinite(k[i].y)) fail(at, "knot is not a finite number");
      if (i > 0 && !(k[i].x > k[i - 1].x))
        fail(at, "knot positions must increase strictly; " + num(k[i].x) + " follows " + num(k[i - 1].x));
      range(at + " value", k[i].y, lo, hi, unit);
    }
  }

 private:
  std::string source_;
};

void validate_vane(const Checker& c, const std::string& side, const VaneParams& v, const FeatherParams& p) {
  if (v.barb_density > 0) {
    c.range(side + ".barb_density", v.barb_density, 1e-3, 20.0, "barbs per mm");
    const double n = v.barb_density * p.vane_length();
    if (n > 5000) c.fail(side + ".barb_density", num(v.barb_density) + " per mm gives " + num(n) +
                                                     " barbs on this side; at most 5000 are allowed");
  } else {
    c.range(side + ".barb_density", v.barb_density, 0.0, 20.0, "barbs per mm (0 = use barbs)");
    c.range(side + ".barbs", v.barbs, 2, 5000);
  }
  c.profile(side + ".width_profile", v.width, 0.0, 2.0 * p.shaft.length, "mm (half-width)");
  if (!(v.width.max_value() > 0)) c.fail(side + ".width_profile", "all widths are 0; the vane needs some width");
  c.profile(side + ".angle_profile", v.angle_deg, 5.0, 90.0, "degrees");
  c.range(side + ".barb_bend_deg", v.barb_bend_deg, 0.0, 80.0, "degrees");
  const SubstructureParams& s = v.substructure;
  const std::string ss = side + ".substructure";
  // The same ranges as the curve file and the renderer (substructure_problem);
  // named here by this file's keys.
  if (const auto bad = substructure_problem(s)) {
    const std::string key = bad->setting == "barbules"    ? "barbules_per_side"
                            : bad->setting == "elevation" ? "elevation_deg"
                            : bad->setting == "azimuth"   ? "azimuth_deg"
                                                          : bad->setting;
    c.fail(ss + "." + key, bad->problem);
  }
}

}  // namespace

void validate(const FeatherParams& p, const std::string& source) {
  const Checker c(source);
  const ShaftParams& s = p.shaft;
  c.range("shaft.length", s.length, kMinShaftLengthMm, kMaxShaftLengthMm, "mm");
  c.range("shaft.calamus_length", s.calamus_length, 0.0, 0.9 * s.length, "mm (at most 0.9 x shaft.length)");
  c.range("shaft.bend_deg", s.bend_deg, -90.0, 90.0, "degrees");
  c.range("shaft.arch_deg", s.arch_deg, -90.0, 90.0, "degrees");
  c.range("shaft.radius_base", s.radius_base, 1e-4, 20.0, "mm");
  c.range("shaft.radius_tip", s.radius_tip, 1e-4, 20.0, "mm");
  c.range("shaft.control_points", s.control_points, 4, 256);
  validate_vane(c, "left", p.left, p);
  validate_vane(c, "right", p.right, p);
  c.range("barb.radius_root", p.barb.radius_root, 1e-5, 5.0, "mm");
  c.range("barb.radius_tip", p.barb.radius_tip, 1e-5, 5.0, "mm");
  c.range("barb.control_points", p.barb.control_points, 4, 64);
  c.range("surface.cupping", p.surface.cupping, -1.0, 1.0, "(depth / width)");
  c.range("surface.twist_deg", p.surface.twist_deg, -180.0, 180.0, "degrees");
  c.range("surface.cage_columns", p.surface.cage_columns, 4, 256);
  c.range("surface.cage_rows", p.surface.cage_rows, 2, 64);
  c.range("afterfeather.fraction", p.afterfeather.fraction, 0.0, 1.0);
  c.range("afterfeather.radius", p.afterfeather.radius, kMinDownRadiusMm, 5.0, "mm");
  c.range("afterfeather.cover", p.afterfeather.cover, 0.01, 1.0);
  c.range("afterfeather.wave", p.afterfeather.wave, 0.0, 50.0, "mm");
  c.range("afterfeather.lift", p.afterfeather.lift, 0.0, 50.0, "mm");
  c.range("afterfeather.waves", p.afterfeather.waves, 0.0, 20.0);
  c.range("splits.count", p.splits.count, 0, 100);
  c.range("splits.gap", p.splits.gap, 0.0, 50.0, "mm");
  c.range("splits.depth", p.splits.depth, 0.01, 1.0);
  c.range("jitter.angle_deg", p.jitter.angle_deg, 0.0, 30.0, "degrees");
  c.range("jitter.spacing", p.jitter.spacing, 0.0, 0.9, "(fraction of the barb spacing)");
  for (int i = 0; i < 3; ++i) c.range("albedo[" + std::to_string(i) + "]", double(p.albedo[i]), 0.0, 1.0);
}

// ---------------------------------------------------------------------------
// JSON reading: every object is read through Reader, over the project's
// JsonReader (json_reader.h): a key present sets its setting, an absent one keeps
// the default, and the keys left over in an object (a typo) are reported.
namespace {

class Reader {
 public:
  explicit Reader(JsonReader j) : j_(std::move(j)) { j_.expect_object(); }

  std::optional<JsonReader> find(const std::string& k) const { return j_.find(k); }
  void number(const std::string& k, double& out) const {
    if (const auto v = j_.find(k)) out = v->number();
  }
  void number(const std::string& k, float& out) const {
    if (const auto v = j_.find(k)) out = float(v->number());
  }
  // Ranges are the validator's (validate); this only keeps an int an int.
  void integer(const std::string& k, int& out) const {
    if (const auto v = j_.find(k)) out = int(v->integer(-1000000000, 1000000000));
  }
  void boolean(const std::string& k, bool& out) const {
    if (const auto v = j_.find(k)) out = v->boolean();
  }
  void string(const std::string& k, std::string& out) const {
    if (const auto v = j_.find(k)) out = v->string();
  }
  void profile(const std::string& k, Profile& out) const {
    const auto v = j_.find(k);
    if (!v) return;
    if (!v->value().is_array()) v->fail(std::string("expected an array of [position, value] pairs, got ") + v->value().type_name());
    std::vector<glm::dvec2> knots;
    for (const JsonReader& e : v->elements()) {
      const json& pair = e.value();
      if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
        e.fail("expected [position, value] (two numbers), got " + pair.dump());
      knots.push_back({pair[0].get<double>(), pair[1].get<double>()});
    }
    out = Profile(std::move(knots));
  }
  void object(const std::string& k, const std::function<void(Reader&)>& body) const {
    if (const auto v = j_.find(k)) {
      Reader r(*v);
      body(r);
      r.finish();
    }
  }
  void finish() const { j_.finish(); }

 private:
  JsonReader j_;
};

void read_vane(Reader& r, VaneParams& v) {
  r.integer("barbs", v.barbs);
  r.number("barb_density", v.barb_density);
  r.profile("width_profile", v.width);
  r.profile("angle_profile", v.angle_deg);
  r.number("barb_bend_deg", v.barb_bend_deg);
  r.object("substructure", [&](Reader& s) {
    SubstructureParams& p = v.substructure;
    s.integer("barbules_per_side", p.barbules_per_side);
    s.number("ramus_radius", p.ramus_radius);
    s.number("barbule_radius", p.barbule_radius);
    s.number("elevation_deg", p.elevation_deg);
    s.number("azimuth_deg", p.azimuth_deg);
    s.number("hooked_fraction", p.hooked_fraction);
    s.number("ribbon_width", p.ribbon_width);
  });
}

json profile_json(const Profile& p) {
  json a = json::array();
  for (const auto& k : p.knots()) a.push_back({k.x, k.y});
  return a;
}

json vane_json(const VaneParams& v) {
  const SubstructureParams& s = v.substructure;
  json j = {{"width_profile", profile_json(v.width)},
            {"angle_profile", profile_json(v.angle_deg)},
            {"barb_bend_deg", v.barb_bend_deg},
            {"substructure",
             {{"barbules_per_side", s.barbules_per_side}, {"ramus_radius", s.ramus_radius},
              {"barbule_radius", s.barbule_radius}, {"elevation_deg", s.elevation_deg},
              {"azimuth_deg", s.azimuth_deg}, {"hooked_fraction", s.hooked_fraction},
              {"ribbon_width", s.ribbon_width}}}};
  if (v.barb_density > 0) j["barb_density"] = v.barb_density;
  else j["barbs"] = v.barbs;
  return j;
}

}  // namespace

FeatherParams params_from_json(const json& j, const std::string& source) {
  FeatherParams p = default_feather_params();
  const Reader r{JsonReader(j, source)};
  r.string("name", p.name);
  r.string("description", p.description);
  r.object("shaft", [&](Reader& s) {
    s.number("length", p.shaft.length);
    s.number("calamus_length", p.shaft.calamus_length);
    s.number("bend_deg", p.shaft.bend_deg);
    s.number("arch_deg", p.shaft.arch_deg);
    s.number("radius_base", p.shaft.radius_base);
    s.number("radius_tip", p.shaft.radius_tip);
    s.integer("control_points", p.shaft.control_points);
  });
  r.object("left", [&](Reader& v) { read_vane(v, p.left); });
  r.object("right", [&](Reader& v) { read_vane(v, p.right); });
  r.object("barb", [&](Reader& b) {
    b.number("radius_root", p.barb.radius_root);
    b.number("radius_tip", p.barb.radius_tip);
    b.integer("control_points", p.barb.control_points);
  });
  r.object("surface", [&](Reader& s) {
    s.number("cupping", p.surface.cupping);
    s.number("twist_deg", p.surface.twist_deg);
    s.integer("cage_columns", p.surface.cage_columns);
    s.integer("cage_rows", p.surface.cage_rows);
  });
  r.object("afterfeather", [&](Reader& a) {
    a.boolean("enabled", p.afterfeather.enabled);
    a.number("fraction", p.afterfeather.fraction);
    a.number("radius", p.afterfeather.radius);
    a.number("cover", p.afterfeather.cover);
    a.number("wave", p.afterfeather.wave);
    a.number("lift", p.afterfeather.lift);
    a.number("waves", p.afterfeather.waves);
  });
  r.object("splits", [&](Reader& s) {
    s.integer("count", p.splits.count);
    if (const auto v = s.find("seed")) {
      if (!v->value().is_number_unsigned()) v->fail("expected a non-negative integer, got " + v->value().dump());
      p.splits.seed = v->value().get<std::uint64_t>();
    }
    s.number("gap", p.splits.gap);
    s.number("depth", p.splits.depth);
  });
  r.object("jitter", [&](Reader& s) {
    s.number("angle_deg", p.jitter.angle_deg);
    s.number("spacing", p.jitter.spacing);
  });
  if (const auto a = r.find("albedo")) {
    const json& v = a->value();
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      a->fail("expected [r, g, b] (three numbers in [0,1], linear), got " + v.dump());
    p.albedo = {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
  }
  r.finish();
  validate(p, source);
  return p;
}

json params_to_json(const FeatherParams& p) {
  json j = {
      {"name", p.name},
      {"description", p.description},
      {"shaft",
       {{"length", p.shaft.length}, {"calamus_length", p.shaft.calamus_length}, {"bend_deg", p.shaft.bend_deg},
        {"arch_deg", p.shaft.arch_deg}, {"radius_base", p.shaft.radius_base}, {"radius_tip", p.shaft.radius_tip},
        {"control_points", p.shaft.control_points}}},
      {"left", vane_json(p.left)},
      {"right", vane_json(p.right)},
      {"barb",
       {{"radius_root", p.barb.radius_root}, {"radius_tip", p.barb.radius_tip},
        {"control_points", p.barb.control_points}}},
      {"surface",
       {{"cupping", p.surface.cupping}, {"twist_deg", p.surface.twist_deg},
        {"cage_columns", p.surface.cage_columns}, {"cage_rows", p.surface.cage_rows}}},
      {"afterfeather",
       {{"enabled", p.afterfeather.enabled}, {"fraction", p.afterfeather.fraction},
        {"radius", p.afterfeather.radius}, {"cover", p.afterfeather.cover}, {"wave", p.afterfeather.wave},
        {"lift", p.afterfeather.lift}, {"waves", p.afterfeather.waves}}},
      {"splits", {{"count", p.splits.count}, {"gap", p.splits.gap}, {"depth", p.splits.depth}}},
      {"jitter", {{"angle_deg", p.jitter.angle_deg}, {"spacing", p.jitter.spacing}}},
      {"albedo", {p.albedo.x, p.albedo.y, p.albedo.z}}};
  if (p.splits.seed) j["splits"]["seed"] = *p.splits.seed;
  return j;
}

FeatherParams parse_params(const std::string& text, const std::string& source) {
  const json j = parse_json(text, source);
  return params_from_json(j, source);
}

FeatherParams read_params(const std::filesystem::path& path) {
  return parse_params(read_json_text(path), path.string());
}

}  // namespace plumage
