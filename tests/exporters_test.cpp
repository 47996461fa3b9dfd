// Exporters: each output is read back by a small tokenizer written here from the
// target format's rules (not from the exporter), and checked against the feather.
#include "plumage/common/exporters.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "feather_samples.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"

using namespace plumage;

namespace {

// strtof, not from_chars: an independent way to read the numbers back.
float to_f(const std::string& s) {
  char* end = nullptr;
  const float v = std::strtof(s.c_str(), &end);
  EXPECT_EQ(*end, '\0') << "not a number: '" << s << "'";
  return v;
}

// ----------------------------------------------------------------- pbrt ---
// A pbrt file is a sequence of directives (capitalised words), each followed by
// positional arguments and "type name" [ values ] parameter lists; '#' comments.
struct PbrtParam {
  std::string type;
  std::vector<std::string> values;  // strings without their quotes
};
struct PbrtStatement {
  std::string directive;
  std::vector<std::string> args;
  std::map<std::string, PbrtParam> params;
};

std::vector<PbrtStatement> parse_pbrt(const std::string& text) {
  std::vector<std::string> tokens;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
      continue;
    }
    if (c == '#') {
      i = text.find('\n', i);
      if (i == std::string::npos) break;
      continue;
    }
    if (c == '[' || c == ']') {
      tokens.emplace_back(1, c);
      ++i;
      continue;
    }
    if (c == '"') {
      const std::size_t close = text.find('"', i + 1);
      EXPECT_NE(close, std::string::npos) << "unterminated string";
      if (close == std::string::npos) return {};
      tokens.push_back(text.substr(i, close - i + 1));
      i = close + 1;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j])) && text[j] != '[' &&
           text[j] != ']' && text[j] != '"')
      ++j;
    tokens.push_back(text.substr(i, j - i));
    i = j;
  }
  std::vector<PbrtStatement> out;
  auto unquote = [](const std::string& t) { return t.substr(1, t.size() - 2); };
  for (std::size_t i = 0; i < tokens.size();) {
    const std::string& t = tokens[i];
    EXPECT_TRUE(std::isupper(static_cast<unsigned char>(t[0]))) << "expected a directive, got " << t;
    PbrtStatement s{t, {}, {}};
    ++i;
    while (i < tokens.size() && !std::isupper(static_cast<unsigned char>(tokens[i][0]))) {
      const std::string& a = tokens[i];
      if (a[0] == '"' && a.find(' ') != std::string::npos) {  // "type name"
        std::istringstream tn(unquote(a));
        PbrtParam p;
        std::string name;
        tn >> p.type >> name;
        ++i;
        EXPECT_LT(i, tokens.size());
        if (tokens[i] == "[") {
          ++i;
          while (i < tokens.size() && tokens[i] != "]") {
            EXPECT_NE(tokens[i], "[") << "nested bracket";
            p.values.push_back(tokens[i][0] == '"' ? unquote(tokens[i]) : tokens[i]);
            ++i;
          }
          EXPECT_LT(i, tokens.size()) << "unbalanced '['";
          ++i;  // ']'
        } else {
          p.values.push_back(tokens[i][0] == '"' ? unquote(tokens[i]) : tokens[i]);
          ++i;
        }
        EXPECT_FALSE(s.params.count(name)) << "parameter given twice: " << name;
        s.params[name] = p;
      } else {
        EXPECT_NE(a, "]") << "unbalanced ']'";
        EXPECT_NE(a, "[") << "bracket outside a parameter list";
        s.args.push_back(a[0] == '"' ? unquote(a) : a);
        ++i;
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

// The radius plumage draws control point k with (DESIGN §4; feather.h), written out
// here from the design rather than taken from render_radii(): a barb at W / 2 but over
// the last kBarbTipTaper of its control polygon, where it eases (smoothstep) to its
// own radius at the tip; a one-segment barb at W / 2 throughout.
float drawn_radius(const Feather& f, const Curve& c, std::size_t k) {
  const ControlPoint& p = c.points[k];
  if (c.kind != CurveKind::Barb) return p.radius;  // the shaft and down barbs keep their own radii
  const float w = (c.side == VaneSide::Right ? f.right : f.left).ribbon_width;
  if (!(w > 0)) return p.radius;
  float before = 0, total = 0;
  for (std::size_t i = 1; i < c.points.size(); ++i) {
    const float d = glm::length(c.points[i].p - c.points[i - 1].p);
    total += d;
    if (i <= k) before += d;
  }
  if (c.points.size() <= 4 || !(std::isfinite(kBarbTipTaper * total) && total > 0)) return w / 2;
  const float t = std::clamp((total - before) / (kBarbTipTaper * total), 0.0f, 1.0f);
  const float own = std::min(p.radius, w / 2);
  return t >= 1 ? w / 2 : std::min(own + t * t * (3 - 2 * t) * (w / 2 - own), w / 2);
}

glm::vec3 vec3_of(const std::vector<std::string>& v, std::size_t at = 0) {
  EXPECT_GE(v.size(), at + 3);
  if (v.size() < at + 3) return glm::vec3(0);
  return {to_f(v[at]), to_f(v[at + 1]), to_f(v[at + 2])};
}

float float_param(const PbrtStatement& s, const std::string& name) {
  EXPECT_TRUE(s.params.count(name)) << s.directive << " has no " << name;
  if (!s.params.count(name)) return std::nanf("");
  EXPECT_EQ(s.params.at(name).values.size(), 1u) << name;
  return to_f(s.params.at(name).values.at(0));
}

// What a pbrt file says, read back: its camera, lights, card, material and curves.
struct PbrtScene {
  std::vector<float> look_at;  // 9 numbers
  bool mirrored = false;       // Scale -1 1 1 before LookAt
  float fov = 0;
  int spp = 0, max_depth = -1, width = 0, height = 0;
  std::vector<ExportSphereLight> lights;
  std::optional<glm::vec3> environment;
  std::vector<glm::vec3> card_corners;
  glm::vec3 card_albedo{0};
  std::optional<PbrtStatement> hair;
};

PbrtScene check_pbrt(const std::string& text, const Feather& f, bool v4) {
  const std::set<std::string> known = {"Scale",          "LookAt",          "Camera",       "Sampler",
                                       "Integrator",     "PixelFilter",     "Film",         "WorldBegin",
                                       "WorldEnd",       "LightSource",     "AttributeBegin", "AttributeEnd",
                                       "AreaLightSource", "Translate",      "Material",     "Shape"};
  PbrtScene scene;
  const auto statements = parse_pbrt(text);
  EXPECT_FALSE(statements.empty());
  int depth = 0;
  bool world = false;
  std::string material;  // of the current attribute block
  bool emitting = false;
  glm::vec3 area_L(0), translate(0);
  std::size_t curve = 0;
  for (const PbrtStatement& s : statements) {
    SCOPED_TRACE(s.directive);
    EXPECT_TRUE(known.count(s.directive)) << "unknown directive";
    if (s.directive == "WorldBegin") world = true;
    if (s.directive == "WorldEnd") {
      EXPECT_FALSE(v4) << "pbrt-v4 has no WorldEnd";
    }
    if (s.directive == "Scale") scene.mirrored = s.args == std::vector<std::string>{"-1", "1", "1"} && !world;
    if (s.directive == "AttributeBegin") ++depth;
    if (s.directive == "AttributeEnd") {
      EXPECT_GE(--depth, 0);
      material.clear();
      emitting = false;
      translate = glm::vec3(0);
    }
    if (s.directive == "LookAt") {
      EXPECT_EQ(s.args.size(), 9u);
      for (const std::string& a : s.args) scene.look_at.push_back(to_f(a));
    }
    if (s.directive == "Camera") {
      EXPECT_EQ(s.args, std::vector<std::string>{"perspective"});
      scene.fov = float_param(s, "fov");
    }
    if (s.directive == "Sampler") scene.spp = int(float_param(s, "pixelsamples"));
    if (s.directive == "Integrator") {
      EXPECT_EQ(s.args, std::vector<std::string>{v4 ? "volpath" : "path"});
      scene.max_depth = int(float_param(s, "maxdepth"));
    }
    if (s.directive == "PixelFilter") {
      EXPECT_EQ(s.args, std::vector<std::string>{"box"});
    }
    if (s.directive == "Film") {
      scene.width = int(float_param(s, "xresolution"));
      scene.height = int(float_param(s, "yresolution"));
    }
    if (s.directive == "LightSource") {
      EXPECT_EQ(s.args, std::vector<std::string>{"infinite"});
      scene.environment = vec3_of(s.params.at("L").values);
    }
    if (s.directive == "AreaLightSource") {
      EXPECT_EQ(s.args, std::vector<std::string>{"diffuse"});
      EXPECT_EQ(s.params.at("L").type, "rgb");
      area_L = vec3_of(s.params.at("L").values);
      emitting = true;
    }
    if (s.directive == "Translate") translate = vec3_of(s.args);
    if (s.directive == "Material") {
      EXPECT_TRUE(world);
      EXPECT_EQ(s.args.size(), 1u);
      material = s.args.at(0);
      if (material == "hair") {
        // The absorption itself: pbrt's "color"/"reflectance" would apply pbrt's own albedo mapping.
        EXPECT_EQ(s.params.at("sigma_a").type, "rgb");
        EXPECT_FALSE(s.params.count("color") || s.params.count("reflectance"));
        scene.hair = s;
      } else {
        EXPECT_EQ(material, v4 ? "diffuse" : "matte");
        scene.card_albedo = vec3_of(s.params.at(v4 ? "reflectance" : "Kd").values);
      }
    }
    if (s.directive != "Shape") continue;
    EXPECT_TRUE(world) << "shape before WorldBegin";
    EXPECT_EQ(depth, 1) << "every shape sits in its own attribute block";
    if (s.args == std::vector<std::string>{"sphere"}) {
      EXPECT_TRUE(emitting) << "a sphere is an LED: emitting, placed by Translate";
      scene.lights.push_back({translate, float_param(s, "radius"), area_L});
      continue;
    }
    if (s.args == std::vector<std::string>{"trianglemesh"}) {
      EXPECT_EQ(material, v4 ? "diffuse" : "matte");
      const auto& P = s.params.at("P");
      EXPECT_EQ(P.type, v4 ? "point3" : "point");
      EXPECT_EQ(P.values.size(), 12u);
      for (std::size_t k = 0; k + 2 < P.values.size(); k += 3) scene.card_corners.push_back(vec3_of(P.values, k));
      EXPECT_EQ(s.params.at("indices").values, (std::vector<std::string>{"0", "1", "2", "0", "2", "3"}));
      continue;
    }
    EXPECT_EQ(s.args, std::vector<std::string>{"curve"});
    EXPECT_EQ(material, "hair") << "a curve without the hair material";
    if (curve >= f.curves.size()) {
      ADD_FAILURE() << "more curves than the feather has";
      continue;
    }
    const Curve& c = f.curves[curve++];
    const std::size_t n = c.points.size();
    EXPECT_EQ(s.params.at("basis").values, std::vector<std::string>{"bspline"});
    const PbrtParam& P = s.params.at("P");
    EXPECT_EQ(P.type, v4 ? "point3" : "point");
    EXPECT_EQ(P.values.size(), 3 * n);
    if (P.values.size() != 3 * n) continue;
    for (std::size_t k = 0; k < n; ++k)
      for (int a = 0; a < 3; ++a) EXPECT_EQ(to_f(P.values[3 * k + a]), c.points[k].p[a]);
    // Widths are the full width (2 r) of the drawn radius B-spline at the curve's
    // ends, held inside the float range; a barb keeps its root's width to the tip
    // (pbrt's width is linear over the whole curve: the tip taper is left out).
    auto full_width = [&](std::size_t k) {
      const auto r = [&](std::size_t i) { return double(drawn_radius(f, c, i)); };
      const double w = (r(k) + 4.0 * r(k + 1) + r(k + 2)) / 3.0;
      return std::min(w, double(std::numeric_limits<float>::max()));
    };
    const double w0 = float_param(s, "width0"), w1 = float_param(s, "width1");
    EXPECT_NEAR(w0, full_width(0), 1e-6 * full_width(0) + 1e-38);
    const double end = c.kind == CurveKind::Barb ? full_width(0) : full_width(n - 3);
    EXPECT_NEAR(w1, end, 1e-6 * end + 1e-38);
    // Hair mode's barbs face the ray ("flat"); the shaft and down barbs are round.
    EXPECT_EQ(s.params.at("type").values.at(0), c.kind == CurveKind::Barb ? "flat" : "cylinder");
    EXPECT_FALSE(s.params.count("N"));
  }
  EXPECT_EQ(curve, f.curves.size());
  EXPECT_EQ(depth, 0);
  EXPECT_TRUE(scene.hair.has_value() || f.curves.empty());
  if (!v4) {
    EXPECT_EQ(statements.back().directive, "WorldEnd");
  }
  return scene;
}

// -------------------------------------------------------------- mitsuba ---
void check_mitsuba(const std::string& text, const Feather& f) {
  std::vector<std::vector<glm::vec4>> curves(1);
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) {
      EXPECT_FALSE(curves.back().empty()) << "two blank lines in a row";
      curves.emplace_back();
      continue;
    }
    std::istringstream ls(line);
    std::vector<std::string> w;
    for (std::string t; ls >> t;) w.push_back(t);
    ASSERT_EQ(w.size(), 4u) << "line '" << line << "': Mitsuba wants x y z radius";
    curves.back().push_back({to_f(w[0]), to_f(w[1]), to_f(w[2]), to_f(w[3])});
  }
  if (f.curves.empty()) {
    EXPECT_TRUE(text.empty());
    return;
  }
  ASSERT_EQ(curves.size(), f.curves.size());
  for (std::size_t i = 0; i < curves.size(); ++i) {
    ASSERT_EQ(curves[i].size(), f.curves[i].points.size());
    ASSERT_GE(curves[i].size(), 4u);
    for (std::size_t k = 0; k < curves[i].size(); ++k) {
      const ControlPoint& p = f.curves[i].points[k];
      EXPECT_EQ(curves[i][k], glm::vec4(p.p, drawn_radius(f, f.curves[i], k)));
    }
  }
}

// ------------------------------------------------------------------ obj ---
void check_obj(const std::string& text, const Feather& f) {
  std::vector<glm::vec3> v;
  std::istringstream in(text);
  std::string line;
  std::string cstype;
  int deg = -1;
  std::size_t objects = 0, curve = 0;
  bool open = false;  // between curv and end
  std::size_t curv_n = 0;
  double u0 = 0, u1 = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    if (!(ls >> key) || key[0] == '#') continue;
    std::vector<std::string> w;
    for (std::string t; ls >> t;) w.push_back(t);
    if (key == "v") {
      ASSERT_EQ(w.size(), 3u);
      v.push_back({to_f(w[0]), to_f(w[1]), to_f(w[2])});
    } else if (key == "o") {
      ASSERT_EQ(w.size(), 1u);
      ++objects;
    } else if (key == "cstype") {
      ASSERT_EQ(w.size(), 1u);
      cstype = w[0];
    } else if (key == "deg") {
      ASSERT_EQ(w.size(), 1u);
      deg = std::atoi(w[0].c_str());
    } else if (key == "curv") {
      ASSERT_FALSE(open) << "curv inside another curve's body";
      ASSERT_EQ(cstype, "bspline");
      ASSERT_EQ(deg, 3);
      ASSERT_GE(w.size(), 2u + 4u);
      ASSERT_LT(curve, f.curves.size());
      const Curve& c = f.curves[curve++];
      u0 = std::atof(w[0].c_str());
      u1 = std::atof(w[1].c_str());
      curv_n = w.size() - 2;
      ASSERT_EQ(curv_n, c.points.size());
      for (std::size_t k = 0; k < curv_n; ++k) {
        const long idx = std::atol(w[2 + k].c_str());
        // Positive indices count from the first v of the file; negative ones back from the last.
        const long abs_idx = idx > 0 ? idx : long(v.size()) + idx + 1;
        ASSERT_GE(abs_idx, 1);
        ASSERT_LE(abs_idx, long(v.size())) << "curv references a vertex not yet defined";
        EXPECT_EQ(v[abs_idx - 1], c.points[k].p);
      }
      open = true;
    } else if (key == "parm") {
      ASSERT_TRUE(open);
      ASSERT_EQ(w.at(0), "u");
      // A degree-3 B-spline with n control points has n + 4 knots, non-decreasing,
      // and its curve is defined on [knot[3], knot[n]].
      ASSERT_EQ(w.size() - 1, curv_n + 4);
      std::vector<double> knots;
      for (std::size_t k = 1; k < w.size(); ++k) knots.push_back(std::atof(w[k].c_str()));
      for (std::size_t k = 1; k < knots.size(); ++k) EXPECT_LE(knots[k - 1], knots[k]);
      EXPECT_GE(u0, knots[3]);
      EXPECT_LE(u1, knots[curv_n]);
      EXPECT_LT(u0, u1);
      // Uniform knots: the curve is our uniform B-spline, not a clamped one.
      for (std::size_t k = 1; k < knots.size(); ++k)
        EXPECT_DOUBLE_EQ(knots[k] - knots[k - 1], knots[1] - knots[0]);
    } else if (key == "end") {
      ASSERT_TRUE(open);
      open = false;
    } else {
      ADD_FAILURE() << "unexpected OBJ statement: " << line;
    }
  }
  EXPECT_FALSE(open) << "missing end";
  EXPECT_EQ(curve, f.curves.size());
  EXPECT_EQ(objects, f.curves.size());
  EXPECT_EQ(v.size(), f.num_control_points());
}

// ------------------------------------------------------- mitsuba scene ---
// Just enough XML for the scene file: a prolog, comments, elements with quoted
// attributes, no text content.
struct XmlElement {
  std::string tag;
  std::map<std::string, std::string> attrs;
  std::vector<XmlElement> children;
  const XmlElement* child(const std::string& tag, const std::string& name = "") const {
    for (const XmlElement& c : children)
      if (c.tag == tag && (name.empty() || (c.attrs.count("name") && c.attrs.at("name") == name))) return &c;
    return nullptr;
  }
  std::vector<const XmlElement*> all(const std::string& tag, const std::string& type = "") const {
    std::vector<const XmlElement*> r;
    for (const XmlElement& c : children)
      if (c.tag == tag && (type.empty() || (c.attrs.count("type") && c.attrs.at("type") == type))) r.push_back(&c);
    return r;
  }
  std::string value(const std::string& tag, const std::string& name) const {
    const XmlElement* c = child(tag, name);
    EXPECT_NE(c, nullptr) << "<" << tag << " name=\"" << name << "\"> missing in <" << this->tag << ">";
    return c && c->attrs.count("value") ? c->attrs.at("value") : "";
  }
};

struct XmlReader {
  const std::string& t;
  std::size_t i = 0;
  void skip() {
    for (;;) {
      while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) ++i;
      if (t.compare(i, 4, "<!--") == 0) {
        const std::size_t e = t.find("-->", i + 4);
        EXPECT_NE(e, std::string::npos) << "unterminated comment";
        EXPECT_EQ(t.substr(i + 4, e - i - 4).find("--"), std::string::npos) << "'--' inside a comment";
        i = e == std::string::npos ? t.size() : e + 3;
      } else if (t.compare(i, 2, "<?") == 0) {
        const std::size_t e = t.find("?>", i);
        i = e == std::string::npos ? t.size() : e + 2;
      } else {
        return;
      }
    }
  }
  std::string name() {
    const std::size_t b = i;
    while (i < t.size() && (std::isalnum(static_cast<unsigned char>(t[i])) || t[i] == '_')) ++i;
    return t.substr(b, i - b);
  }
  XmlElement element() {
    XmlElement e;
    skip();
    EXPECT_EQ(t[i], '<');
    ++i;
    e.tag = name();
    for (;;) {
      while (std::isspace(static_cast<unsigned char>(t[i]))) ++i;
      if (t.compare(i, 2, "/>") == 0) {
        i += 2;
        return e;
      }
      if (t[i] == '>') {
        ++i;
        break;
      }
      const std::string key = name();
      EXPECT_FALSE(key.empty()) << "bad attribute at " << i;
      if (key.empty()) return e;
      EXPECT_EQ(t[i], '=');
      EXPECT_EQ(t[i + 1], '"');
      const std::size_t close = t.find('"', i + 2);
      std::string v = t.substr(i + 2, close - i - 2);
      EXPECT_EQ(v.find('<'), std::string::npos);
      EXPECT_FALSE(e.attrs.count(key)) << "attribute given twice: " << key;
      e.attrs[key] = v;
      i = close + 1;
    }
    for (;;) {
      skip();
      if (t.compare(i, 2, "</") == 0) {
        i += 2;
        EXPECT_EQ(name(), e.tag) << "mismatched closing tag";
        EXPECT_EQ(t[i], '>');
        ++i;
        return e;
      }
      if (i >= t.size()) {
        ADD_FAILURE() << "<" << e.tag << "> not closed";
        return e;
      }
      e.children.push_back(element());
    }
  }
};

XmlElement parse_xml(const std::string& text) {
  XmlReader r{text};
  XmlElement root = r.element();
  r.skip();
  EXPECT_EQ(r.i, text.size()) << "text after the root element";
  return root;
}

// "x, y, z"
glm::vec3 xml_vec3(const std::string& v) {
  glm::vec3 r(0);
  EXPECT_EQ(std::sscanf(v.c_str(), "%f, %f, %f", &r.x, &r.y, &r.z), 3) << v;
  return r;
}

// The Mitsuba scene read back into an ExportScene (and the curves file it names).
ExportScene check_mitsuba_scene(const std::string& text, std::string* curves_file = nullptr) {
  ExportScene s;
  const XmlElement scene = parse_xml(text);
  EXPECT_EQ(scene.tag, "scene");
  EXPECT_EQ(scene.attrs.at("version"), "3.0.0");
  const auto integrators = scene.all("integrator", "path");
  EXPECT_EQ(integrators.size(), 1u);
  if (!integrators.empty()) s.max_depth = std::stoi(integrators[0]->value("integer", "max_depth")) - 1;
  const auto sensors = scene.all("sensor", "perspective");
  EXPECT_EQ(sensors.size(), 1u);
  if (!sensors.empty()) {
    const XmlElement& c = *sensors[0];
    s.camera.fov_deg = to_f(c.value("float", "fov"));
    EXPECT_EQ(c.value("string", "fov_axis"), "y");
    const XmlElement* look = c.child("transform", "to_world") ? c.child("transform", "to_world")->child("lookat") : nullptr;
    EXPECT_NE(look, nullptr);
    if (look) {
      s.camera.eye = xml_vec3(look->attrs.at("origin"));
      s.camera.look_at = xml_vec3(look->attrs.at("target"));
      s.camera.up = xml_vec3(look->attrs.at("up"));
    }
    s.spp = std::stoi(c.child("sampler")->value("integer", "sample_count"));
    const XmlElement* film = c.child("film");
    s.width = std::stoi(film->value("integer", "width"));
    s.height = std::stoi(film->value("integer", "height"));
    EXPECT_EQ(film->child("rfilter")->attrs.at("type"), "box");
  }
  for (const XmlElement* sphere : scene.all("shape", "sphere")) {
    const XmlElement* emitter = sphere->child("emitter");
    EXPECT_TRUE(emitter && emitter->attrs.at("type") == "area");
    s.lights.push_back({xml_vec3(sphere->value("point", "center")), to_f(sphere->value("float", "radius")),
                        emitter ? xml_vec3(emitter->value("rgb", "radiance")) : glm::vec3(0)});
  }
  for (const XmlElement* env : scene.all("emitter", "constant")) s.environment = xml_vec3(env->value("rgb", "radiance"));
  for (const XmlElement* rect : scene.all("shape", "rectangle")) {
    const XmlElement* tw = rect->child("transform", "to_world");
    const glm::vec3 scale = xml_vec3(tw->child("scale")->attrs.at("value"));
    EXPECT_EQ(scale.x, scale.y);
    EXPECT_EQ(scale.z, 1.0f);
    EXPECT_EQ(tw->children.at(0).tag, "scale") << "scale, then translate";
    const XmlElement* bsdf = rect->child("bsdf");
    EXPECT_EQ(bsdf->attrs.at("type"), "diffuse");
    s.card = ExportCard{xml_vec3(tw->child("translate")->attrs.at("value")), scale.x, xml_vec3(bsdf->value("rgb", "reflectance"))};
  }
  const auto curves = scene.all("shape", "bsplinecurve");
  EXPECT_EQ(curves.size(), 1u);
  if (!curves.empty()) {
    if (curves_file) *curves_file = curves[0]->value("string", "filename");
    const XmlElement* hair = curves[0]->child("bsdf");
    EXPECT_EQ(hair->attrs.at("type"), "hair");
    s.material.sigma_a = xml_vec3(hair->value("rgb", "sigma_a"));
    s.material.beta_m = to_f(hair->value("float", "longitudinal_roughness"));
    s.material.beta_n = to_f(hair->value("float", "azimuthal_roughness"));
    s.material.alpha_deg = -to_f(hair->value("float", "scale_tilt"));  // Mitsuba's sign is pbrt's
    EXPECT_EQ(to_f(hair->value("float", "ext_ior")), 1.0f);
    s.material.eta = to_f(hair->value("float", "int_ior"));
  }
  return s;
}

// A scene with a bit of everything, nothing at its default value.
ExportScene busy_scene() {
  ExportScene s;
  s.image_filename = "busy.exr";
  s.width = 300;
  s.height = 200;
  s.spp = 17;
  s.max_depth = 5;
  s.camera = {{1, 2, 300}, {1, 2, 0}, {0, 1, 0}, 25};
  s.lights = {{{10, 20, 250}, 2.5f, {700, 710, 720}}, {{-40, 5, 240}, 3, {1, 2, 3}}};
  s.environment = glm::vec3(0.25f, 0.5f, 0.75f);
  s.card = ExportCard{{1, 2, -3}, 150, {0.8f, 0.7f, 0.6f}};
  s.material = {{0.49f, 0.48f, 0.45f}, 0.25f, 0.35f, 2.5f, 1.5f};
  return s;
}

void expect_same_scene(const ExportScene& got, const ExportScene& want, bool pbrt_fov) {
  EXPECT_EQ(got.width, want.width);
  EXPECT_EQ(got.height, want.height);
  EXPECT_EQ(got.spp, want.spp);
  EXPECT_EQ(got.max_depth, want.max_depth);
  EXPECT_EQ(got.camera.eye, want.camera.eye);
  EXPECT_EQ(got.camera.look_at, want.camera.look_at);
  EXPECT_EQ(got.camera.up, want.camera.up);
  EXPECT_EQ(got.camera.fov_deg, pbrt_fov ? pbrt_fov_deg(want) : want.camera.fov_deg);
  ASSERT_EQ(got.lights.size(), want.lights.size());
  for (std::size_t i = 0; i < got.lights.size(); ++i) {
    EXPECT_EQ(got.lights[i].centre, want.lights[i].centre) << "light " << i;
    EXPECT_EQ(got.lights[i].radius, want.lights[i].radius) << "light " << i;
    EXPECT_EQ(got.lights[i].radiance, want.lights[i].radiance) << "light " << i;
  }
  EXPECT_EQ(got.environment, want.environment);
  EXPECT_EQ(got.material.sigma_a, want.material.sigma_a);
  EXPECT_EQ(got.material.beta_m, want.material.beta_m);
  EXPECT_EQ(got.material.beta_n, want.material.beta_n);
  EXPECT_EQ(got.material.alpha_deg, want.material.alpha_deg);
  EXPECT_EQ(got.material.eta, want.material.eta);
}

// A pbrt file's scene as an ExportScene (fov as pbrt has it), for expect_same_scene.
ExportScene as_export_scene(const PbrtScene& p, bool v4) {
  ExportScene s;
  s.width = p.width;
  s.height = p.height;
  s.spp = p.spp;
  s.max_depth = p.max_depth;
  if (p.look_at.size() == 9)
    s.camera = {{p.look_at[0], p.look_at[1], p.look_at[2]}, {p.look_at[3], p.look_at[4], p.look_at[5]},
                {p.look_at[6], p.look_at[7], p.look_at[8]}, p.fov};
  s.lights = p.lights;
  s.environment = p.environment;
  if (p.hair) {
    s.material.sigma_a = vec3_of(p.hair->params.at("sigma_a").values);
    s.material.beta_m = float_param(*p.hair, "beta_m");
    s.material.beta_n = float_param(*p.hair, "beta_n");
    s.material.alpha_deg = -float_param(*p.hair, "alpha");  // pbrt's sign is the opposite of plumage's
    s.material.eta = float_param(*p.hair, "eta");
  }
  (void)v4;
  return s;
}

// ---------------------------------------------------------------- blender ---
// Every number on a line of Python (tuples of floats and ints).
std::vector<float> py_numbers(const std::string& line) {
  std::vector<float> out;
  for (std::size_t i = 0; i < line.size();) {
    const char c = line[i];
    if (c == '#') break;
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.') {
      char* end = nullptr;
      const float v = std::strtof(line.c_str() + i, &end);
      const std::size_t next = std::size_t(end - line.c_str());
      if (next == i) {  // a lone '-' or '.'
        ++i;
        continue;
      }
      out.push_back(v);
      i = next;
    } else {
      ++i;
    }
  }
  return out;
}

// The script's data block read back: its curves and the scene's numbers.
void check_blender(const std::string& text, const Feather& f, const ExportScene& want) {
  std::istringstream in(text);
  std::string line;
  std::map<std::string, std::vector<float>> constants;
  std::vector<std::vector<float>> curves, leds;
  std::vector<std::vector<float>>* list = nullptr;
  while (std::getline(in, line)) {
    if (line == "CURVES = [") list = &curves;
    else if (line == "LEDS = [") list = &leds;
    else if (line == "]") list = nullptr;
    else if (list) list->push_back(py_numbers(line));
    else if (const std::size_t eq = line.find(" = "); eq != std::string::npos && std::isupper(static_cast<unsigned char>(line[0])))
      constants[line.substr(0, eq)] = py_numbers(line.substr(eq + 3));
  }
  ASSERT_EQ(curves.size(), f.curves.size());
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const Curve& c = f.curves[i];
    ASSERT_EQ(curves[i].size(), 4 * c.points.size()) << "curve " << i;
    for (std::size_t k = 0; k < c.points.size(); ++k)
      EXPECT_EQ(glm::vec4(curves[i][4 * k], curves[i][4 * k + 1], curves[i][4 * k + 2], curves[i][4 * k + 3]),
                glm::vec4(c.points[k].p, drawn_radius(f, c, k)));
  }
  const auto& m = want.material;
  EXPECT_EQ(constants["SIGMA_A"], (std::vector<float>{m.sigma_a.x, m.sigma_a.y, m.sigma_a.z}));
  EXPECT_EQ(constants["BETA_M, BETA_N, ETA"], (std::vector<float>{m.beta_m, m.beta_n, m.eta}));
  EXPECT_EQ(constants["ALPHA_DEG"], std::vector<float>{-m.alpha_deg});
  EXPECT_EQ(constants["FOV_Y_DEG"], std::vector<float>{want.camera.fov_deg});
  EXPECT_EQ(constants["WIDTH, HEIGHT, SPP, MAX_DEPTH"],
            (std::vector<float>{float(want.width), float(want.height), float(want.spp), float(want.max_depth)}));
  const auto& c = want.camera;
  EXPECT_EQ(constants["CAMERA_EYE, CAMERA_TARGET, CAMERA_UP"],
            (std::vector<float>{c.eye.x, c.eye.y, c.eye.z, c.look_at.x, c.look_at.y, c.look_at.z, c.up.x, c.up.y, c.up.z}));
  ASSERT_EQ(leds.size(), want.lights.size());
  for (std::size_t i = 0; i < leds.size(); ++i) {
    const ExportSphereLight& l = want.lights[i];
    EXPECT_EQ(leds[i], (std::vector<float>{l.centre.x, l.centre.y, l.centre.z, l.radius, l.radiance.x, l.radiance.y,
                                           l.radiance.z}));
  }
  if (want.card) {
    const ExportCard& k = *want.card;
    EXPECT_EQ(constants["CARD"], (std::vector<float>{k.centre.x, k.centre.y, k.centre.z, k.half_side, k.albedo.x,
                                                     k.albedo.y, k.albedo.z}));
  }
}

}  // namespace

TEST(Exporters, PbrtCarriesTheSceneAndTheCurves) {
  const Feather f = samples::sample_feather(9, 6);
  const ExportScene want = busy_scene();
  for (bool v4 : {true, false}) {
    SCOPED_TRACE(v4 ? "pbrt-v4" : "pbrt-v3");
    const std::string text = v4 ? format_pbrt_v4(f, want) : format_pbrt_v3(f, want);
    const PbrtScene got = check_pbrt(text, f, v4);
    expect_same_scene(as_export_scene(got, v4), want, true);
    EXPECT_TRUE(got.mirrored);
    EXPECT_EQ(got.card_albedo, want.card->albedo);
    ASSERT_EQ(got.card_corners.size(), 4u);
    for (const glm::vec3& c : got.card_corners) {
      EXPECT_EQ(c.z, want.card->centre.z);
      EXPECT_EQ(std::fabs(c.x - want.card->centre.x), want.card->half_side);
      EXPECT_EQ(std::fabs(c.y - want.card->centre.y), want.card->half_side);
    }
    // Counter-clockwise seen from +Z: the card faces the feather.
    const glm::vec3 n = glm::cross(got.card_corners[1] - got.card_corners[0], got.card_corners[2] - got.card_corners[0]);
    EXPECT_GT(n.z, 0);
    EXPECT_NE(text.find("\"busy.exr\""), std::string::npos);
  }
}

TEST(Exporters, PbrtFovIsThatOfTheShorterSide) {
  ExportScene s;
  s.camera.fov_deg = 30;
  s.width = 640;
  s.height = 480;
  EXPECT_EQ(pbrt_fov_deg(s), 30.0f);  // landscape: the vertical side is the shorter one
  s.width = 300;
  s.height = 600;  // portrait: pbrt's fov is horizontal, tan(fov_x / 2) = tan(15°) / 2
  EXPECT_NEAR(std::tan(pbrt_fov_deg(s) * std::numbers::pi / 360), std::tan(std::numbers::pi / 12) / 2, 1e-6);
}

TEST(Exporters, SubstructureIsExportedAsHairWithAComment) {
  const Feather f = samples::sample_feather(3, 5);
  ExportScene s = busy_scene();
  for (const char* mode : {"substructure", "explicit"}) {
    s.shading = mode;
    for (const std::string& text : {format_pbrt_v4(f, s), format_pbrt_v3(f, s),
                                    format_mitsuba_scene(f, s, "c.txt")}) {
      EXPECT_NE(text.find(std::string(mode) + " mode (rami and barbules inside each barb) has no counterpart"),
                std::string::npos);
      EXPECT_NE(text.find("hair fibres of the same width"), std::string::npos);
    }
  }
  s.shading = "hair";
  EXPECT_EQ(format_pbrt_v3(f, s).find("no counterpart"), std::string::npos);
}

TEST(Exporters, MitsubaHasFourNumbersPerLineAndBlankLinesBetweenCurves) {
  Feather f = samples::sample_feather(9, 6);
  f.left.ribbon_width = 0.3f;  // left barbs at W / 2, right barbs at their own radius
  const std::string text = format_mitsuba_curves(f);
  EXPECT_EQ(text.find('#'), std::string::npos) << "Mitsuba's loader takes no comments";
  check_mitsuba(text, f);
}

TEST(Exporters, MitsubaSceneCarriesTheSceneAndNamesTheCurves) {
  const Feather f = samples::sample_feather(9, 6);
  const ExportScene want = busy_scene();
  std::string curves;
  const ExportScene got = check_mitsuba_scene(format_mitsuba_scene(f, want, "a&b \"c\".txt"), &curves);
  expect_same_scene(got, want, false);
  ASSERT_TRUE(got.card);
  EXPECT_EQ(got.card->centre, want.card->centre);
  EXPECT_EQ(got.card->half_side, want.card->half_side);
  EXPECT_EQ(got.card->albedo, want.card->albedo);
  EXPECT_EQ(curves, "a&amp;b &quot;c&quot;.txt");  // escaped in the attribute
}

TEST(Exporters, BlenderScriptCarriesTheCurvesWithRadiusAndTheScene) {
  Feather f = samples::sample_feather(9, 6);
  f.right.ribbon_width = 0.25f;
  f.provenance.source = "photo:a \"quoted\" \\ name.jpg";
  const std::string text = format_blender(f, busy_scene());
  check_blender(text, f, busy_scene());
  EXPECT_NE(text.find("NAME = \"photo:a \\\"quoted\\\" \\\\ name.jpg\"\n"), std::string::npos);
  EXPECT_NE(text.find("ShaderNodeBsdfHairPrincipled"), std::string::npos);
  EXPECT_NE(text.find("bpy.ops.object.convert(target=\"CURVES\")"), std::string::npos);
}

TEST(Exporters, ObjCurvesReferenceValidVerticesAndKnots) {
  const Feather f = samples::sample_feather(9, 6);
  check_obj(format_obj(f), f);
}

TEST(Exporters, RandomFeathersExportToEveryFormat) {
  std::mt19937_64 rng(99);
  const ExportScene scene = busy_scene();
  for (int i = 0; i < 200; ++i) {
    SCOPED_TRACE("feather " + std::to_string(i));
    const Feather f = samples::random_feather(rng);
    check_pbrt(format_pbrt_v4(f, scene), f, true);
    check_pbrt(format_pbrt_v3(f, scene), f, false);
    check_mitsuba(format_mitsuba_curves(f), f);
    check_mitsuba_scene(format_mitsuba_scene(f, scene, "f.txt"));
    check_obj(format_obj(f), f);
    check_blender(format_blender(f, scene), f, scene);
  }
}

TEST(Exporters, FormatNames) {
  for (ExportFormat e : {ExportFormat::Fcurves, ExportFormat::Pbrt, ExportFormat::PbrtV3,
                         ExportFormat::Mitsuba, ExportFormat::Obj, ExportFormat::Blender})
    EXPECT_EQ(parse_export_format(to_string(e)), e);
  EXPECT_EQ(parse_export_format("pbrt-v3"), ExportFormat::PbrtV3);
  try {
    parse_export_format("usd");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fcurves, pbrt, pbrt-v3, mitsuba, obj, blender"), std::string::npos)
        << e.what();
  }
}

TEST(Exporters, InvalidFeatherWritesNothing) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("plumage_exporters_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Feather bad = samples::sample_feather(2, 4);
  bad.curves[1].points[2].p.y = std::numeric_limits<float>::infinity();
  for (ExportFormat e : {ExportFormat::Fcurves, ExportFormat::Pbrt, ExportFormat::PbrtV3,
                         ExportFormat::Mitsuba, ExportFormat::Obj, ExportFormat::Blender}) {
    SCOPED_TRACE(to_string(e));
    const fs::path out = dir / (std::string("out") + default_extension(e));
    const std::string before = fs::exists(out) ? read_file(out) : "(none)";
    EXPECT_THROW(export_feather(out, bad, e, ExportScene{}), Error);
    EXPECT_EQ(fs::exists(out) ? read_file(out) : "(none)", before);
    // A good export replaces the file whole, and the fcurves export reads back.
    const Feather good = samples::sample_feather(2, 4);
    export_feather(out, good, e, busy_scene());
    EXPECT_EQ(read_file(out), export_text(good, e, busy_scene()));
    if (e == ExportFormat::Mitsuba) {
      EXPECT_EQ(read_file(mitsuba_scene_path(out)), format_mitsuba_scene(good, busy_scene(), "out.txt"));
    }
  }
  EXPECT_EQ(read_fcurves(dir / "out.fcurves"), samples::sample_feather(2, 4));
  std::size_t files = 0;
  for ([[maybe_unused]] auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 6u);  // out.fcurves, out.pbrt (both pbrt flavours), out.txt + out.xml, out.obj, out.py; no temporaries
  fs::remove_all(dir);
}

// A scene of placed feathers: each feather's material reaches its own object, a bad
// scene is refused naming what is wrong and writes nothing, and fcurves is refused.
TEST(Exporters, InstancesCarryEachFeathersMaterialAndRefuseBadScenes) {
  const Feather a = samples::sample_feather(3, 4), b = samples::sample_feather(5, 4);
  ExportInstances in;
  ExportMaterial dark, pale;
  dark.sigma_a = glm::vec3(2.5f, 3.0f, 3.5f);
  pale.sigma_a = glm::vec3(0.125f, 0.25f, 0.5f);
  in.feathers = {{"dark", &a, dark}, {"pale.1", &b, pale}};
  glm::mat4 m(1.0f);
  m[3] = glm::vec4(10, -20, 30, 1);
  in.placements = {{0, glm::mat4(1.0f)}, {1, m}, {0, m}};
  const ExportScene s = busy_scene();
  for (const std::string& text : {format_pbrt_v4(in, s), format_pbrt_v3(in, s)}) {
    const std::size_t d = text.find("ObjectBegin \"dark\""), p = text.find("ObjectBegin \"pale.1\"");
    ASSERT_NE(d, std::string::npos);
    ASSERT_NE(p, std::string::npos);
    // Each object's material is the one written after its ObjectBegin.
    EXPECT_NE(text.find("\"rgb sigma_a\" [ 2.5 3 3.5 ]", d), std::string::npos);
    EXPECT_LT(text.find("\"rgb sigma_a\" [ 2.5 3 3.5 ]", d), p);
    EXPECT_NE(text.find("\"rgb sigma_a\" [ 0.125 0.25 0.5 ]", p), std::string::npos);
    EXPECT_NE(text.find("Transform [ 1 0 0 0 0 1 0 0 0 0 1 0 10 -20 30 1 ]"), std::string::npos);
  }
  const std::string xml = format_mitsuba_scene(in, s, {"a.txt", "b.txt"});
  EXPECT_NE(xml.find("<matrix value=\"1 0 0 10 0 1 0 -20 0 0 1 30 0 0 0 1\"/>"), std::string::npos);
  EXPECT_NE(xml.find("value=\"0.125, 0.25, 0.5\""), std::string::npos) << xml;
  EXPECT_THROW(format_mitsuba_scene(in, s, {"a.txt"}), Error);
  // OBJ: 3 placements of 3-barb and 5-barb feathers (and their shafts).
  const std::string obj = format_obj(in);
  std::size_t objects = 0;
  for (std::size_t at = obj.find("\no "); at != std::string::npos; at = obj.find("\no ", at + 1)) ++objects;
  EXPECT_EQ(objects, 2 * a.curves.size() + b.curves.size());
  EXPECT_NE(obj.find("o p2_dark_shaft"), std::string::npos);

  const auto refused = [&](ExportInstances bad, const std::string& says) {
    try {
      format_pbrt_v4(bad, s);
      ADD_FAILURE() << "accepted: " << says;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  ExportInstances bad = in;
  bad.feathers[1].name = "has space";
  refused(bad, "is not 1-64 letters");
  bad = in;
  bad.feathers[1].name = "dark";
  refused(bad, "given twice");
  bad = in;
  bad.placements[2].feather = 2;
  refused(bad, "names feather 2 of 2");
  bad = in;
  bad.placements[1].to_world[3][1] = std::numeric_limits<float>::quiet_NaN();
  refused(bad, "non-finite transform");
  bad = in;
  bad.placements.clear();
  refused(bad, "needs a feather and a placement");

  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("plumage_instances_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  bad = in;
  bad.feathers[0].name = "";
  for (ExportFormat e : {ExportFormat::Fcurves, ExportFormat::Pbrt, ExportFormat::PbrtV3, ExportFormat::Mitsuba,
                         ExportFormat::Obj, ExportFormat::Blender})
    EXPECT_THROW(export_instances(dir / "out.x", bad, e, s), Error) << to_string(e);
  EXPECT_THROW(export_instances(dir / "out.fcurves", in, ExportFormat::Fcurves, s), Error);
  EXPECT_TRUE(fs::is_empty(dir));
  export_instances(dir / "m.txt", in, ExportFormat::Mitsuba, s);
  EXPECT_EQ(read_file(dir / "m.dark.txt"), format_mitsuba_curves(a));
  EXPECT_EQ(read_file(dir / "m.pale.1.txt"), format_mitsuba_curves(b));
  EXPECT_EQ(read_file(dir / "m.xml"), format_mitsuba_scene(in, s, {"m.dark.txt", "m.pale.1.txt"}));
  EXPECT_FALSE(fs::exists(dir / "m.txt"));
  fs::remove_all(dir);
}
