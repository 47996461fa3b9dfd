// plumage info: what a .fcurves file holds, at a glance (docs/cli.md#info).
#include <algorithm>
#include <charconv>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "plumage/pipeline/feather_scene.h"

#include "command.h"
#include "plumage/common/bspline.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/number_text.h"
#include "plumage/common/text.h"

namespace plumage::cli {
namespace {

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  double sum = 0;
  std::size_t n = 0;
  void add(double v) { lo = std::min(lo, v), hi = std::max(hi, v), sum += v, ++n; }
  double mean() const { return n ? sum / double(n) : 0.0; }
};

struct Summary {
  std::size_t shafts = 0, barbs = 0, down = 0, left = 0, right = 0, control_points = 0;  // barbs counts down barbs too
  Range points_per_barb, barb_length, barb_radius, shaft_radius;
  double shaft_length = 0;
  Bounds3 bounds;  // of the curve centrelines
};

BSpline3 centreline(const Curve& c) {
  std::vector<glm::dvec3> p;
  p.reserve(c.points.size());
  for (const ControlPoint& q : c.points) p.emplace_back(q.p);
  return BSpline3(std::move(p));
}

Summary summarize(const Feather& f) {
  Summary s;
  for (const Curve& c : f.curves) {
    const BSpline3 line = centreline(c);
    const Bounds3 b = tight_bounds(line);
    s.bounds.extend(b.lo);
    s.bounds.extend(b.hi);
    s.control_points += c.points.size();
    Range& radius = c.kind == CurveKind::Shaft ? s.shaft_radius : s.barb_radius;
    for (const ControlPoint& p : c.points) radius.add(p.radius);
    if (c.kind == CurveKind::Shaft) {
      ++s.shafts;
      s.shaft_length = arc_length(line);
    } else {
      ++s.barbs;
      s.down += c.kind == CurveKind::Down;
      (c.side == VaneSide::Left ? s.left : s.right) += 1;
      s.barb_length.add(arc_length(line));
      s.points_per_barb.add(double(c.points.size()));
    }
  }
  return s;
}

// The double nearest the float's shortest decimal form: JSON shows 0.42, not 0.41999998688697815.
double decimal(float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  double d = v;
  std::from_chars(buf, r.ptr, d);
  return d;
}

nlohmann::json substructure_json(const SubstructureParams& p) {
  return {{"barbules", p.barbules_per_side},
          {"ramus_radius", decimal(p.ramus_radius)},
          {"barbule_radius", decimal(p.barbule_radius)},
          {"elevation", decimal(p.elevation_deg)},
          {"azimuth", decimal(p.azimuth_deg)},
          {"hooked_fraction", decimal(p.hooked_fraction)},
          {"ribbon_width", decimal(p.ribbon_width)}};
}

void print_json(std::ostream& out, const std::string& file, const Feather& f, const Summary& s) {
  nlohmann::json j;
  j["file"] = file;
  j["format_version"] = kFcurvesVersion;
  j["units"] = f.units;
  j["source"] = f.provenance.source;
  j["seed"] = f.provenance.seed ? nlohmann::json(*f.provenance.seed) : nlohmann::json(nullptr);
  j["curves"] = {{"shaft", s.shafts}, {"barbs", s.barbs}, {"down", s.down}, {"left", s.left}, {"right", s.right}};
  j["control_points"] = s.control_points;
  if (!s.bounds.empty())
    j["bounds"] = {{"min", {s.bounds.lo.x, s.bounds.lo.y, s.bounds.lo.z}},
                   {"max", {s.bounds.hi.x, s.bounds.hi.y, s.bounds.hi.z}}};
  if (s.shafts) j["shaft_length"] = s.shaft_length;
  if (s.barbs)
    j["barb_length"] = {{"min", s.barb_length.lo}, {"mean", s.barb_length.mean()}, {"max", s.barb_length.hi}};
  j["substructure"] = {{"left", substructure_json(f.left)}, {"right", substructure_json(f.right)}};
  j["albedo"] = {
      {"color", {decimal(f.albedo.color.x), decimal(f.albedo.color.y), decimal(f.albedo.color.z)}}};
  if (!f.albedo.texture.empty())
    j["albedo"]["texture"] = {{"file", f.albedo.texture},
                              {"rect",
                               {decimal(f.albedo.rect_min.x), decimal(f.albedo.rect_min.y),
                                decimal(f.albedo.rect_max.x), decimal(f.albedo.rect_max.y)}}};
  const auto rgb = [&](const glm::vec3& c) { return nlohmann::json::array({decimal(c.x), decimal(c.y), decimal(c.z)}); };
  if (f.albedo.scale != 1.0f) j["albedo"]["scale"] = decimal(f.albedo.scale);
  if (!f.albedo.shaft.empty()) {  // from the root to the tip
    j["albedo"]["shaft"] = nlohmann::json::array();
    for (const glm::vec3& c : f.albedo.shaft) j["albedo"]["shaft"].push_back(rgb(c));
  }
  j["down_cover"] = decimal(f.down_cover);
  j["medulla"] = {{"ratio", decimal(f.medulla.ratio)},
                  {"sigma_s", rgb(f.medulla.sigma_s)},
                  {"sigma_a", rgb(f.medulla.sigma_a)}};
  out << json_text(j, 2) << "\n";
}

void print_text(std::ostream& out, const std::string& file, const Feather& f, const Summary& s) {
  auto row = [&](const char* key) -> std::ostream& { return out << std::left << std::setw(15) << key; };
  row("file") << file << " (fcurves " << kFcurvesVersion << ", units " << f.units << ")\n";
  row("source") << (f.provenance.source.empty() ? "(not recorded)" : f.provenance.source);
  if (f.provenance.seed) out << ", seed " << *f.provenance.seed;
  out << "\n";
  row("curves") << s.shafts << " shaft, " << s.barbs << " barbs (" << s.left << " left, " << s.right
                << " right";
  if (s.down) out << "; " << s.down << " of them down, their tubes filled " << num(f.down_cover);
  out << ")\n";
  row("control pts") << s.control_points;
  if (s.barbs) out << " (" << num(s.points_per_barb.lo) << ".." << num(s.points_per_barb.hi) << " per barb)";
  out << "\n";
  if (!s.bounds.empty()) {
    const glm::dvec3 size = s.bounds.hi - s.bounds.lo;
    row("bounds (mm)") << "x [" << num(s.bounds.lo.x) << ", " << num(s.bounds.hi.x) << "]  y ["
                       << num(s.bounds.lo.y) << ", " << num(s.bounds.hi.y) << "]  z [" << num(s.bounds.lo.z)
                       << ", " << num(s.bounds.hi.z) << "]  size " << num(size.x) << " x " << num(size.y)
                       << " x " << num(size.z) << " (centrelines)\n";
  }
  if (s.shafts)
    row("shaft") << "length " << num(s.shaft_length) << " mm, radius " << num(s.shaft_radius.lo) << ".."
                 << num(s.shaft_radius.hi) << " mm\n";
  if (s.barbs)
    row("barbs") << "length min " << num(s.barb_length.lo) << " / mean " << num(s.barb_length.mean())
                 << " / max " << num(s.barb_length.hi) << " mm, radius " << num(s.barb_radius.lo) << ".."
                 << num(s.barb_radius.hi) << " mm\n";
  for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
    const SubstructureParams& p = f.substructure(side);
    row(side == VaneSide::Left ? "substructure L" : "substructure R")
        << "N " << p.barbules_per_side << ", r_r " << num(p.ramus_radius) << " mm, r_b "
        << num(p.barbule_radius) << " mm, theta_b " << num(p.elevation_deg) << " deg, phi_b "
        << num(p.azimuth_deg) << " deg, hooked " << num(p.hooked_fraction) << ", W " << num(p.ribbon_width)
        << " mm\n";
  }
  row("albedo") << "color " << num(f.albedo.color.x) << " " << num(f.albedo.color.y) << " "
                << num(f.albedo.color.z);
  if (!f.albedo.texture.empty())
    out << "; texture \"" << f.albedo.texture << "\" on x [" << num(f.albedo.rect_min.x) << ", "
        << num(f.albedo.rect_max.x) << "] y [" << num(f.albedo.rect_min.y) << ", " << num(f.albedo.rect_max.y)
        << "] mm";
  if (f.albedo.scale != 1.0f) out << ", times " << num(f.albedo.scale);
  if (!f.albedo.shaft.empty()) {
    const auto colour = [&](const glm::vec3& c) { return num(c.x) + " " + num(c.y) + " " + num(c.z); };
    out << "; shaft " << colour(f.albedo.shaft.front());
    if (f.albedo.shaft.size() > 1)
      out << " at the root to " << colour(f.albedo.shaft.back()) << " at the tip (" << f.albedo.shaft.size()
          << " stations)";
  }
  out << "\n";
  row("medulla");
  if (f.medulla.ratio > 0)
    out << "ratio " << num(f.medulla.ratio) << ", sigma_s " << num(f.medulla.sigma_s.x) << " " << num(f.medulla.sigma_s.y)
        << " " << num(f.medulla.sigma_s.z) << ", sigma_a " << num(f.medulla.sigma_a.x) << " " << num(f.medulla.sigma_a.y)
        << " " << num(f.medulla.sigma_a.z) << " per radius\n";
  else
    out << "none (clear fibres)\n";
}

// A scene of many feathers: its placements, its distinct feathers and their barbs.
void print_scene(std::ostream& out, const std::string& file, const LoadedScene& loaded, bool json) {
  const FeatherScene& sc = loaded.scene;
  std::vector<std::size_t> uses(sc.feathers.size(), 0);
  std::size_t mirrored = 0;
  for (const ScenePlacement& p : sc.placements) {
    ++uses[p.feather];
    if (similarity_of(p.to_world)->mirrored) ++mirrored;
  }
  if (json) {
    nlohmann::ordered_json j;
    j["file"] = file;
    j["format"] = "fscene";
    j["placements"] = sc.placements.size();
    j["distinct_feathers"] = sc.feathers.size();
    j["barbs"] = loaded.placed_barbs();
    j["mirrored_placements"] = mirrored;
    j["feathers"] = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < sc.feathers.size(); ++i) {
      const SceneFeather& f = sc.feathers[i];
      j["feathers"].push_back({{"name", f.name},
                               {"source", to_string(f.source)},
                               {"from", f.source == SceneFeatherSource::Preset ? f.preset : f.path},
                               {"barbs", loaded.feathers[i].count(CurveKind::Barb)},
                               {"placements", uses[i]}});
    }
    out << json_text(j, 2) << "\n";
    return;
  }
  out << file << ": scene of " << sc.placements.size() << " placements (" << mirrored << " mirrored) of "
      << sc.feathers.size() << " distinct feathers, " << loaded.placed_barbs() << " barbs over all placements\n";
  for (std::size_t i = 0; i < sc.feathers.size(); ++i) {
    const SceneFeather& f = sc.feathers[i];
    out << "  " << f.name << ": "
        << to_string(f.source) << ' ' << (f.source == SceneFeatherSource::Preset ? f.preset : f.path)
        << (f.source == SceneFeatherSource::Layout ? " feather " + std::to_string(f.layout_feather) : "")
        << (f.source != SceneFeatherSource::Fcurves ? " seed " + std::to_string(f.seed) : "")
        << ", " << loaded.feathers[i].count(CurveKind::Barb) << " barbs, placed " << uses[i] << "x\n";
  }
}

struct InfoArgs {
  std::string input;
  bool json = false;
};

const Registration kInfo{
    "info", "Summarise a .fcurves file (curve counts, bounds, lengths, substructure, albedo, provenance) or a .fscene",
    [](CLI::App& sub) -> std::function<int()> {
      auto args = std::make_shared<InfoArgs>();
      sub.footer(
          "Reads the whole file with the strict reader, so it doubles as a validator: a\n"
          "malformed file is reported as FILE:LINE:COL: message.\n"
          "Lengths are arc lengths of the B-spline centrelines; bounds are their tight\n"
          "bounds (radii not included).\n"
          "A .fscene scene is summarised by its placements, distinct feathers and barbs over all\n"
          "placements (docs/scene-format.md); its feathers are read or generated to count them.\n"
          "Example: plumage info feather.fcurves --json\n"
          "Exit status: 0 done, 1 the file could not be read or is malformed, 2 usage error.\n");
      sub.add_option("FILE", args->input, "The .fcurves or .fscene file to read")->required();
      sub.add_flag("--json", args->json, "Print the summary as JSON (for scripts)");
      return [args]() -> int {
        if (std::filesystem::path(args->input).extension() == ".fscene") {
          print_scene(std::cout, args->input, load_scene(args->input), args->json);
          return 0;
        }
        const Feather f = read_fcurves(args->input);
        const Summary s = summarize(f);
        if (args->json)
          print_json(std::cout, args->input, f, s);
        else
          print_text(std::cout, args->input, f, s);
        return 0;
      };
    }};

}  // namespace
}  // namespace plumage::cli
