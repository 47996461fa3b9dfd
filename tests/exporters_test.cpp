// Exporters: each output is read back by a small tokenizer written here from the
// target format's rules (not from the exporter), and checked against the feather.
#include "plumage/common/exporters.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
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

void check_pbrt(const std::string& text, const Feather& f, bool v4) {
  const std::set<std::string> known = {
      "Scale",    "LookAt",      "Camera",         "Sampler",      "Integrator", "Film", "WorldBegin",
      "WorldEnd", "LightSource", "AttributeBegin", "AttributeEnd", "Material",   "Shape"};
  const auto statements = parse_pbrt(text);
  ASSERT_FALSE(statements.empty());
  int depth = 0;
  bool world = false, material = false;
  std::size_t curve = 0;
  for (const PbrtStatement& s : statements) {
    SCOPED_TRACE(s.directive);
    EXPECT_TRUE(known.count(s.directive)) << "unknown directive";
    if (s.directive == "WorldBegin") world = true;
    if (s.directive == "WorldEnd") {
      EXPECT_FALSE(v4) << "pbrt-v4 has no WorldEnd";
    }
    if (s.directive == "AttributeBegin") ++depth;
    if (s.directive == "AttributeEnd") {
      EXPECT_GE(--depth, 0);
    }
    if (s.directive == "LookAt") {
      EXPECT_EQ(s.args.size(), 9u);
      for (const std::string& a : s.args) EXPECT_TRUE(std::isfinite(to_f(a))) << a;
    }
    if (s.directive == "Material") {
      ASSERT_EQ(s.args.size(), 1u);
      EXPECT_EQ(s.args[0], "hair");
      const char* key = v4 ? "reflectance" : "color";
      ASSERT_TRUE(s.params.count(key));
      EXPECT_EQ(s.params.at(key).type, "rgb");
      ASSERT_EQ(s.params.at(key).values.size(), 3u);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(to_f(s.params.at(key).values[c]), f.albedo.color[c]);
      material = true;
    }
    if (s.directive != "Shape") continue;
    EXPECT_TRUE(world && material) << "shape before WorldBegin or the material";
    ASSERT_EQ(s.args, std::vector<std::string>{"curve"});
    ASSERT_LT(curve, f.curves.size());
    const Curve& c = f.curves[curve++];
    const std::size_t n = c.points.size();
    EXPECT_EQ(s.params.at("basis").values, std::vector<std::string>{"bspline"});
    const PbrtParam& P = s.params.at("P");
    EXPECT_EQ(P.type, v4 ? "point3" : "point");
    ASSERT_EQ(P.values.size(), 3 * n);
    for (std::size_t k = 0; k < n; ++k)
      for (int a = 0; a < 3; ++a) EXPECT_EQ(to_f(P.values[3 * k + a]), c.points[k].p[a]);
    // Widths are the full width (2 r) of the radius B-spline at the curve's ends,
    // held inside the float range.
    const auto& r = c.points;
    auto full_width = [&](std::size_t k) {
      const double w = (double(r[k].radius) + 4.0 * r[k + 1].radius + r[k + 2].radius) / 3.0;
      return std::min(w, double(std::numeric_limits<float>::max()));
    };
    const double w0 = to_f(s.params.at("width0").values.at(0)), w1 = to_f(s.params.at("width1").values.at(0));
    EXPECT_NEAR(w0, full_width(0), 1e-6 * full_width(0) + 1e-38);
    EXPECT_NEAR(w1, full_width(n - 3), 1e-6 * full_width(n - 3) + 1e-38);
    const std::string type = s.params.at("type").values.at(0);
    if (c.kind == CurveKind::Shaft) {
      EXPECT_EQ(type, "cylinder");
      EXPECT_FALSE(s.params.count("N"));
    } else {
      EXPECT_EQ(type, "ribbon");
      const PbrtParam& N = s.params.at("N");
      EXPECT_EQ(N.type, "normal");
      // pbrt: a ribbon needs one normal per segment joint, (n - 3) + 1 of them.
      ASSERT_EQ(N.values.size(), 3 * (n - 2));
      for (std::size_t k = 0; k + 2 < n; ++k) {
        const glm::vec3 v(to_f(N.values[3 * k]), to_f(N.values[3 * k + 1]), to_f(N.values[3 * k + 2]));
        EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f);
      }
    }
  }
  EXPECT_EQ(curve, f.curves.size());
  EXPECT_EQ(depth, 0);
  if (!v4) {
    EXPECT_EQ(statements.back().directive, "WorldEnd");
  }
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
      EXPECT_EQ(curves[i][k], glm::vec4(p.p, p.radius));
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

}  // namespace

TEST(Exporters, PbrtV4IsWellFormedAndCarriesTheCurves) {
  const Feather f = samples::sample_feather(9, 6);
  check_pbrt(format_pbrt_v4(f), f, true);
}

TEST(Exporters, PbrtV3IsWellFormedAndCarriesTheCurves) {
  const Feather f = samples::sample_feather(9, 6);
  check_pbrt(format_pbrt_v3(f), f, false);
}

TEST(Exporters, MitsubaHasFourNumbersPerLineAndBlankLinesBetweenCurves) {
  const Feather f = samples::sample_feather(9, 6);
  const std::string text = format_mitsuba_curves(f);
  EXPECT_EQ(text.find('#'), std::string::npos) << "Mitsuba's loader takes no comments";
  check_mitsuba(text, f);
}

TEST(Exporters, ObjCurvesReferenceValidVerticesAndKnots) {
  const Feather f = samples::sample_feather(9, 6);
  check_obj(format_obj(f), f);
}

TEST(Exporters, RandomFeathersExportToEveryFormat) {
  std::mt19937_64 rng(99);
  for (int i = 0; i < 200; ++i) {
    SCOPED_TRACE("feather " + std::to_string(i));
    const Feather f = samples::random_feather(rng);
    check_pbrt(format_pbrt_v4(f), f, true);
    check_pbrt(format_pbrt_v3(f), f, false);
    check_mitsuba(format_mitsuba_curves(f), f);
    check_obj(format_obj(f), f);
  }
}

TEST(Exporters, FormatNames) {
  for (ExportFormat e : {ExportFormat::Fcurves, ExportFormat::Pbrt, ExportFormat::PbrtV3,
                         ExportFormat::Mitsuba, ExportFormat::Obj})
    EXPECT_EQ(parse_export_format(to_string(e)), e);
  EXPECT_EQ(parse_export_format("pbrt-v3"), ExportFormat::PbrtV3);
  try {
    parse_export_format("usd");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fcurves, pbrt, pbrt-v3, mitsuba, obj"), std::string::npos)
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
                         ExportFormat::Mitsuba, ExportFormat::Obj}) {
    SCOPED_TRACE(to_string(e));
    const fs::path out = dir / (std::string("out") + default_extension(e));
    const std::string before = fs::exists(out) ? read_file(out) : "(none)";
    EXPECT_THROW(export_feather(out, bad, e), Error);
    EXPECT_EQ(fs::exists(out) ? read_file(out) : "(none)", before);
    // A good export replaces the file whole, and the fcurves export reads back.
    const Feather good = samples::sample_feather(2, 4);
    export_feather(out, good, e);
    EXPECT_EQ(read_file(out), export_text(good, e));
  }
  EXPECT_EQ(read_fcurves(dir / "out.fcurves"), samples::sample_feather(2, 4));
  std::size_t files = 0;
  for ([[maybe_unused]] auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 4u);  // out.fcurves, out.pbrt (both pbrt flavours), out.txt, out.obj; no temporaries
  fs::remove_all(dir);
}
