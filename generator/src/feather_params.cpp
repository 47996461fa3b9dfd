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
  c.range("afterfeather.fraction", p.afterfeather.fraction, 0.0, 0.9);
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
// JSON reading: every object is read through Reader, which remembers the keys it
// consumed so that whatever is left over (a typo) is reported.
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> d(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) d[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t prev = d[0];
    d[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cur = d[j];
      d[j] = std::min({d[j] + 1, d[j - 1] + 1, prev + (a[i - 1] != b[j - 1])});
      prev = cur;
    }
  }
  return d[b.size()];
}

const char* type_name(const json& v) { return v.type_name(); }

class Reader {
 public:
  Reader(const json& j, std::string path, const std::string& source) : j_(j), path_(std::move(path)), source_(source) {
    if (!j_.is_object()) fail(path_.empty() ? "top level" : path_, std::string("expected an object {...}, got ") + type_name(j_));
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw Error(Location{source_}, key + ": " + what);
  }
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }

  const json* find(const std::string& k) {
    seen_.insert(k);
    auto it = j_.find(k);
    return it == j_.end() ? nullptr : &*it;
  }

  void number(const std::string& k, double& out) {
    if (const json* v = find(k)) {
      if (!v->is_number()) fail(key(k), std::string("expected a number, got ") + type_name(*v));
      out = v->get<double>();
    }
  }
  void number(const std::string& k, float& out) {
    double d = out;
    number(k, d);
    out = float(d);
  }
  void integer(const std::string& k, int& out) {
    if (const json* v = find(k)) {
      if (!v->is_number_integer() && !(v->is_number_float() && std::floor(v->get<double>()) == v->get<double>()))
        fail(key(k), std::string("expected an integer, got ") + (v->is_number() ? v->dump() : type_name(*v)));
      const double d = v->get<double>();
      if (d < -1e9 || d > 1e9) fail(key(k), "integer " + v->dump() + " is far out of range");
      out = int(d);
    }
  }
  void boolean(const std::string& k, bool& out) {
    if (const json* v = find(k)) {
      if (!v->is_boolean()) fail(key(k), std::string("expected true or false, got ") + type_name(*v));
      out = v->get<bool>();
    }
  }
  void string(const std::string& k, std::string& out) {
    if (const json* v = find(k)) {
      if (!v->is_string()) fail(key(k), std::string("expected a string, got ") + type_name(*v));
      out = v->get<std::string>();
    }
  }
  void profile(const std::string& k, Profile& out) {
    const json* v = find(k);
    if (!v) return;
    const std::string kk = key(k);
    if (!v->is_array()) fail(kk, std::string("expected an array of [position, value] pairs, got ") + type_name(*v));
    std::vector<glm::dvec2> knots;
    for (std::size_t i = 0; i < v->size(); ++i) {
      const json& e = (*v)[i];
      if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number())
        fail(kk + "[" + std::to_string(i) + "]", "expected [position, value] (two numbers), got " + e.dump());
      knots.push_back({e[0].get<double>(), e[1].get<double>()});
    }
    out = Profile(std::move(knots));
  }
  void object(const std::string& k, const std::function<void(Reader&)>& body) {
    if (const json* v = find(k)) {
      Reader r(*v, key(k), source_);
      body(r);
      r.finish();
    }
  }

  // Unknown keys are errors, with the nearest known key suggested.
  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      if (seen_.count(it.key())) continue;
      std::string best;
      std::size_t best_d = 4;
      for (const auto& s : seen_) {
        const std::size_t d = edit_distance(it.key(), s);
        if (d < best_d) best_d = d, best = s;
      }
      std::string known;
      for (const auto& s : seen_) known += (known.empty() ? "" : ", ") + s;
      fail(key(it.key()), "unknown key" + (best.empty() ? std::string() : " (did you mean '" + best + "'?)") +
                              "; known keys here: " + known);
    }
  }

 private:
  const json& j_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> seen_;
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
  Reader r(j, "", source);
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
    a.number("wave", p.afterfeather.wave);
    a.number("lift", p.afterfeather.lift);
    a.number("waves", p.afterfeather.waves);
  });
  r.object("splits", [&](Reader& s) {
    s.integer("count", p.splits.count);
    if (const json* v = s.find("seed")) {
      if (!v->is_number_unsigned()) s.fail("splits.seed", "expected a non-negative integer, got " + v->dump());
      p.splits.seed = v->get<std::uint64_t>();
    }
    s.number("gap", p.splits.gap);
    s.number("depth", p.splits.depth);
  });
  r.object("jitter", [&](Reader& s) {
    s.number("angle_deg", p.jitter.angle_deg);
    s.number("spacing", p.jitter.spacing);
  });
  if (const json* a = r.find("albedo")) {
    if (!a->is_array() || a->size() != 3 || !(*a)[0].is_number() || !(*a)[1].is_number() || !(*a)[2].is_number())
      r.fail("albedo", "expected [r, g, b] (three numbers in [0,1], linear), got " + a->dump());
    p.albedo = {(*a)[0].get<float>(), (*a)[1].get<float>(), (*a)[2].get<float>()};
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
       {{"enabled", p.afterfeather.enabled}, {"fraction", p.afterfeather.fraction}, {"wave", p.afterfeather.wave},
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
