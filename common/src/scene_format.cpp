// The `.fscene` reader and writer (spec: docs/scene-format.md).
#include "plumage/common/scene_format.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <glm/gtc/matrix_transform.hpp>

#include "float_text.h"
#include "line_reader.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/finite.h"
#include "plumage/common/text.h"

namespace plumage {
namespace {

using detail::append_float;
using detail::append_int;
using detail::append_quoted;
using detail::append_vec3;
using detail::LineReader;
using detail::printable_string;
using detail::Token;

constexpr float kSimilarityTolerance = 1e-4f;



const char* const kPlaceForm =
    "place NAME [scale S] [mirror x|y|z] [rotate RX RY RZ] [translate X Y Z] [matrix M00 M01 M02 M03 M10 .. M23]";

class Reader : LineReader {
 public:
  Reader(std::string_view text, const std::string& filename) : LineReader(text, filename) {}
  FeatherScene parse();

 private:
  void parse_feather(FeatherScene& s);
  void parse_place(FeatherScene& s);
  void parse_camera(FeatherScene& s);
  glm::vec3 vec3_at(std::size_t i, const char* what) const {
    if (i + 3 > tok_.size()) fail(end_column(), std::string(what) + ": expected three numbers X Y Z");
    return {finite_float(tok_[i], what), finite_float(tok_[i + 1], what), finite_float(tok_[i + 2], what)};
  }
  std::map<std::string, std::size_t, std::less<>> names_;
  int units_line_ = 0, camera_line_ = 0, lights_line_ = 0;
};

void Reader::parse_feather(FeatherScene& s) {
  if (tok_.size() < 3)
    fail(end_column(), "feather: expected 'feather NAME fcurves \"FILE\"', 'feather NAME preset PRESET seed N' or "
                       "'feather NAME layout \"FILE\" feather ID seed N'");
  const Token& name = tok_[1];
  if (const std::string bad = scene_name_problem(name.text); !bad.empty()) fail(name, "feather '" + printable(name.text) + "': " + bad);
  if (const auto it = names_.find(name.text); it != names_.end())
    fail(name, "feather '" + std::string(name.text) + "' defined twice (first on line " +
                   std::to_string(s.feathers[it->second].line) + ")");
  if (s.feathers.size() >= kMaxSceneFeathers)
    fail(tok_[0], "more than " + std::to_string(kMaxSceneFeathers) + " feathers: split the scene");
  SceneFeather f;
  f.name = std::string(name.text);
  f.line = line_no_;
  const Token& kind = tok_[2];
  if (kind.text == "fcurves") {
    expect_count(4, "feather NAME fcurves \"FILE\"");
    f.source = SceneFeatherSource::Fcurves;
    f.path = quoted(tok_[3], "feather fcurves");
    if (f.path.empty()) fail(tok_[3], "feather fcurves: the file name is empty");
  } else if (kind.text == "preset") {
    expect_count(6, "feather NAME preset PRESET seed N");
    f.source = SceneFeatherSource::Preset;
    f.preset = std::string(tok_[3].text);
    if (const std::string bad = scene_name_problem(f.preset); !bad.empty()) fail(tok_[3], "feather preset: not a preset name");
    if (tok_[4].text != "seed") fail(tok_[4], "feather preset: expected 'seed N' after the preset's name");
    f.seed = unsigned_int(tok_[5], "feather seed");
  } else if (kind.text == "layout") {
    expect_count(8, "feather NAME layout \"FILE\" feather ID seed N");
    f.source = SceneFeatherSource::Layout;
    f.path = quoted(tok_[3], "feather layout");
    if (f.path.empty()) fail(tok_[3], "feather layout: the file name is empty");
    if (tok_[4].text != "feather")
      fail(tok_[4], "feather layout: expected 'feather ID' after the file (the id analyze gave it, F<id> on its overlay)");
    f.layout_feather = unsigned_int(tok_[5], "feather layout id");
    if (f.layout_feather > kMaxLayoutFeatherId) fail(tok_[5], "feather layout: the id is larger than any layout holds");
    if (tok_[6].text != "seed") fail(tok_[6], "feather layout: expected 'seed N' after the feather's id");
    f.seed = unsigned_int(tok_[7], "feather seed");
  } else {
    fail(kind, "feather: unknown source '" + printable(kind.text) + "' (expected fcurves, preset or layout)");
  }
  names_.emplace(f.name, s.feathers.size());
  s.feathers.push_back(std::move(f));
}

// The operations compose in the order written: each applies to the result of those before it.
void Reader::parse_place(FeatherScene& s) {
  if (tok_.size() < 2) fail(end_column(), std::string("place: expected '") + kPlaceForm + "'");
  const auto it = names_.find(tok_[1].text);
  if (it == names_.end())
    fail(tok_[1], "place: no feather named '" + printable(tok_[1].text) + "' is defined above this line");
  if (s.placements.size() >= kMaxScenePlacements)
    fail(tok_[0], "more than " + std::to_string(kMaxScenePlacements) + " placements: split the scene");
  glm::mat4 m(1.0f);
  std::size_t i = 2;
  while (i < tok_.size()) {
    const Token& op = tok_[i];
    glm::mat4 step(1.0f);
    if (op.text == "scale") {
      if (i + 1 >= tok_.size()) fail(end_column(), "place: expected a number after 'scale'");
      const float k = finite_float(tok_[i + 1], "place scale");
      if (!(k > 0)) fail(tok_[i + 1], "place scale: must be above 0 (mirror with 'mirror x|y|z')");
      step = glm::scale(glm::mat4(1.0f), glm::vec3(k));
      i += 2;
    } else if (op.text == "mirror") {
      if (i + 1 >= tok_.size()) fail(end_column(), "place: expected x, y or z after 'mirror'");
      const std::string_view axis = tok_[i + 1].text;
      if (axis != "x" && axis != "y" && axis != "z") fail(tok_[i + 1], "place mirror: expected x, y or z (the axis it flips)");
      glm::vec3 k(1.0f);
      k[axis == "x" ? 0 : axis == "y" ? 1 : 2] = -1.0f;
      step = glm::scale(glm::mat4(1.0f), k);
      i += 2;
    } else if (op.text == "rotate") {
      const glm::vec3 deg = vec3_at(i + 1, "place rotate (degrees about x, then y, then z)");
      const glm::mat4 rx = glm::rotate(glm::mat4(1.0f), glm::radians(deg.x), glm::vec3(1, 0, 0));
      const glm::mat4 ry = glm::rotate(glm::mat4(1.0f), glm::radians(deg.y), glm::vec3(0, 1, 0));
      const glm::mat4 rz = glm::rotate(glm::mat4(1.0f), glm::radians(deg.z), glm::vec3(0, 0, 1));
      step = rz * ry * rx;
      i += 4;
    } else if (op.text == "translate") {
      step = glm::translate(glm::mat4(1.0f), vec3_at(i + 1, "place translate"));
      i += 4;
    } else if (op.text == "matrix") {
      if (i + 13 > tok_.size()) fail(end_column(), "place matrix: expected 12 numbers, a 3x4 matrix row by row");
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) step[c][r] = finite_float(tok_[i + 1 + std::size_t(4 * r + c)], "place matrix");
      if (!similarity_of(step))
        fail(op, "place matrix: its 3x3 part must be a rotation times one scale above 0, mirrored or not (shear and "
                 "unequal scales would flatten the fibres' round sections)");
      i += 13;
    } else {
      fail(op, "place: unknown operation '" + printable(op.text) + "' (expected scale, mirror, rotate, translate or matrix)");
    }
    m = step * m;
  }
  if (!all_finite(m) || !similarity_of(m))
    fail(tok_[0], "place: the transform overflows a float or its scale is too small; use smaller numbers");
  s.placements.push_back({it->second, m, line_no_});
}

void Reader::parse_camera(FeatherScene& s) {
  if (camera_line_) fail(tok_[0], "second 'camera' record (first on line " + std::to_string(camera_line_) + ")");
  camera_line_ = line_no_;
  if (tok_.size() < 2) fail(end_column(), "camera: expected position X Y Z, look_at X Y Z, up X Y Z or fov DEGREES");
  std::size_t i = 1;
  while (i < tok_.size()) {
    const Token& key = tok_[i];
    if (key.text == "position" || key.text == "look_at" || key.text == "up") {
      std::optional<glm::vec3>& v = key.text == "position" ? s.camera.position
                                    : key.text == "look_at" ? s.camera.look_at
                                                            : s.camera.up;
      if (v) fail(key, "camera: '" + std::string(key.text) + "' given twice");
      v = vec3_at(i + 1, key.text == "up" ? "camera up" : key.text == "position" ? "camera position" : "camera look_at");
      i += 4;
    } else if (key.text == "fov") {
      if (s.camera.fov_deg) fail(key, "camera: 'fov' given twice");
      if (i + 1 >= tok_.size()) fail(end_column(), "camera fov: expected the vertical field of view in degrees");
      const float fov = finite_float(tok_[i + 1], "camera fov");
      if (!(fov > 0 && fov < 180)) fail(tok_[i + 1], "camera fov: must lie in (0, 180) degrees");
      s.camera.fov_deg = fov;
      i += 2;
    } else {
      fail(key, "camera: unknown key '" + printable(key.text) + "' (expected position, look_at, up or fov)");
    }
  }
  if (s.camera.up && !(glm::length(*s.camera.up) > 0)) fail(tok_[0], "camera up: must not be zero");
}

FeatherScene Reader::parse() {
  FeatherScene s;
  read_header("fscene", kFsceneVersion, "a .fscene file");
  for (;;) {
    if (!next_line()) fail(end_column(), "missing 'end' at the end of the file (truncated file?)");
    if (tok_.empty()) continue;
    const std::string_view k = tok_[0].text;
    if (k == "end") {
      expect_count(1, "end");
      break;
    }
    if (k == "units") {
      if (units_line_) fail(tok_[0], "second 'units' record (first on line " + std::to_string(units_line_) + ")");
      units_line_ = line_no_;
      expect_count(2, "units mm");
      if (tok_[1].text != "mm") fail(tok_[1], "units: Plumage works in millimetres; write 'units mm'");
    } else if (k == "feather") {
      parse_feather(s);
    } else if (k == "place") {
      parse_place(s);
    } else if (k == "camera") {
      parse_camera(s);
    } else if (k == "lights") {
      if (lights_line_) fail(tok_[0], "second 'lights' record (first on line " + std::to_string(lights_line_) + ")");
      lights_line_ = line_no_;
      expect_count(2, "lights all|none|1,5,12|2-9");
      s.lights = std::string(tok_[1].text);
    } else {
      fail(tok_[0], "unknown record '" + printable(k) + "' (expected units, feather, place, camera, lights or end)");
    }
  }
  while (next_line())
    if (!tok_.empty()) fail(tok_[0], "text after 'end': a file holds one scene and stops at 'end'");
  if (s.placements.empty()) fail(1, "the scene places no feather: add a 'place NAME' line");
  return s;
}

}  // namespace

std::optional<Similarity> similarity_of(const glm::mat4& m) {
  if (!all_finite(m) || m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1) return std::nullopt;
  const glm::mat3 a(m);
  const glm::mat3 g = glm::transpose(a) * a;  // scale^2 x identity for a similarity
  const float s2 = (g[0][0] + g[1][1] + g[2][2]) / 3.0f;
  if (!(s2 > 0) || !std::isfinite(s2)) return std::nullopt;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::fabs(g[c][r] - (c == r ? s2 : 0.0f)) > kSimilarityTolerance * s2) return std::nullopt;
  Similarity out;
  out.scale = std::sqrt(s2);
  if (!(out.scale > 0) || !std::isfinite(1.0f / out.scale)) return std::nullopt;
  out.rotation = a / out.scale;
  out.mirrored = glm::determinant(a) < 0;
  return out;
}

std::string scene_name_problem(std::string_view name) {
  if (name.empty() || name.size() > 64) return "a feather's name has 1 to 64 characters";
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      return "a feather's name holds only letters, digits, '_', '-' and '.'";
  return {};
}

const char* to_string(SceneFeatherSource source) {
  switch (source) {
    case SceneFeatherSource::Fcurves:
      return "fcurves";
    case SceneFeatherSource::Preset:
      return "preset";
    case SceneFeatherSource::Layout:
      return "layout";
  }
  return "?";
}

void validate_scene(const FeatherScene& s) {
  auto fail = [](const std::string& what) { throw Error("invalid scene: " + what); };
  if (s.feathers.size() > kMaxSceneFeathers) fail("more than " + std::to_string(kMaxSceneFeathers) + " feathers");
  if (s.placements.empty()) fail("it places no feather");
  if (s.placements.size() > kMaxScenePlacements) fail("more than " + std::to_string(kMaxScenePlacements) + " placements");
  for (std::size_t i = 0; i < s.feathers.size(); ++i) {
    const SceneFeather& f = s.feathers[i];
    if (const std::string bad = scene_name_problem(f.name); !bad.empty()) fail("feather " + std::to_string(i) + ": " + bad);
    for (std::size_t j = 0; j < i; ++j)
      if (s.feathers[j].name == f.name) fail("feather '" + f.name + "' defined twice");
    if (f.source != SceneFeatherSource::Preset &&
        (f.path.empty() || !printable_string(f.path) || invalid_utf8_at(f.path) != std::string_view::npos))
      fail("feather '" + f.name + "': its file name is empty, not UTF-8 or holds a control character");
    if (f.source == SceneFeatherSource::Preset && !scene_name_problem(f.preset).empty())
      fail("feather '" + f.name + "': not a preset name");
    if (f.source == SceneFeatherSource::Layout && f.layout_feather > kMaxLayoutFeatherId)
      fail("feather '" + f.name + "': the layout feather id is larger than any layout holds");
  }
  for (std::size_t i = 0; i < s.placements.size(); ++i) {
    const ScenePlacement& p = s.placements[i];
    if (p.feather >= s.feathers.size()) fail("placement " + std::to_string(i) + " names no defined feather");
    if (!similarity_of(p.to_world))
      fail("placement " + std::to_string(i) + ": the transform is not a rotation, a uniform scale and a translation");
  }
  if (s.camera.fov_deg && !(*s.camera.fov_deg > 0 && *s.camera.fov_deg < 180)) fail("camera fov outside (0, 180)");
  for (const auto* v : {&s.camera.position, &s.camera.look_at, &s.camera.up})
    if (*v && !(std::isfinite((*v)->x) && std::isfinite((*v)->y) && std::isfinite((*v)->z))) fail("camera vector not finite");
  if (s.lights) {
    const std::string& l = *s.lights;
    if (l.empty() || !std::all_of(l.begin(), l.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == ',' || c == '-'; }))
      fail("lights '" + printable(l) + "': expected all, none or LED numbers such as 1,5,12 or 2-9");
  }
}

std::string format_fscene(const FeatherScene& s) {
  validate_scene(s);
  std::string out = "fscene " + std::to_string(kFsceneVersion) + "\nunits mm\n";
  for (const SceneFeather& f : s.feathers) {
    out += "feather " + f.name + " " + to_string(f.source) + " ";
    if (f.source == SceneFeatherSource::Preset)
      out += f.preset;
    else
      append_quoted(out, f.path);
    if (f.source == SceneFeatherSource::Layout) {
      out += " feather ";
      append_int(out, f.layout_feather);
    }
    if (f.source != SceneFeatherSource::Fcurves) {
      out += " seed ";
      append_int(out, f.seed);
    }
    out += '\n';
  }
  if (s.camera.position || s.camera.look_at || s.camera.up || s.camera.fov_deg) {
    out += "camera";
    if (s.camera.position) out += " position ", append_vec3(out, *s.camera.position);
    if (s.camera.look_at) out += " look_at ", append_vec3(out, *s.camera.look_at);
    if (s.camera.up) out += " up ", append_vec3(out, *s.camera.up);
    if (s.camera.fov_deg) out += " fov ", append_float(out, *s.camera.fov_deg);
    out += '\n';
  }
  if (s.lights) out += "lights " + *s.lights + "\n";
  for (const ScenePlacement& p : s.placements) {
    out += "place " + s.feathers[p.feather].name + " matrix";
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) out += ' ', append_float(out, p.to_world[c][r]);
    out += '\n';
  }
  out += "end\n";
  return out;
}

void write_fscene(const std::filesystem::path& path, const FeatherScene& scene) {
  write_file_atomic(path, format_fscene(scene));
}

FeatherScene parse_fscene(std::string_view text, const std::string& filename) {
  return Reader(text, filename).parse();
}

FeatherScene read_fscene(const std::filesystem::path& path) {
  if (check_input_file(path, "a scene file") > kJudgedBytes) check_text_head(read_file_head(path), path.string());
  return parse_fscene(read_file(path), path.string());
}

}  // namespace plumage
