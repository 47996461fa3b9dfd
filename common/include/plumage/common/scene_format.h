#pragma once
// The plain-text scene format `.fscene` (docs/scene-format.md): many feathers in
// one scene. It defines feathers by name (a .fcurves file, a species preset with a
// seed, or a feather of an analysed layout.json with a seed) and places them, each placement one feather and an affine
// transform (rotation, uniform scale, mirroring and translation), with an
// optional camera and dome-LED selection. A feather defined once and placed many
// times is built once (instancing; renderer/world.h).
//
// The reader is strict and reports FILE:LINE:COL, like the .fcurves reader it
// shares its tokenizer with; the writer round-trips (write -> read -> write gives
// identical bytes).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace plumage {

inline constexpr int kFsceneVersion = 1;
// Bounds that keep a hostile file from asking for unbounded work or memory.
inline constexpr std::size_t kMaxSceneFeathers = 4096;
inline constexpr std::size_t kMaxScenePlacements = 1u << 20;
// A layout feather's id is an int in layout.json; larger ids name no feather.
inline constexpr std::uint64_t kMaxLayoutFeatherId = 2147483647;

enum class SceneFeatherSource { Fcurves, Preset, Layout };

// One feather the scene defines (`feather NAME ...`).
struct SceneFeather {
  std::string name;  // letters, digits, '_', '-', '.'; unique in the scene
  SceneFeatherSource source = SceneFeatherSource::Fcurves;
  std::string path;    // Fcurves, Layout: the curve file or layout.json, relative to the scene file's folder unless absolute
  std::string preset;  // Preset: the preset's name (plumage generate --list-presets)
  std::uint64_t layout_feather = 0;  // Layout: the feather's id in the layout (F<id> on analyze's overlay)
  std::uint64_t seed = 1;  // Preset, Layout: the generator's seed
  int line = 0;            // where it was defined (0 for a scene not read from text)
};

// One placement (`place NAME ...`): feather `feather` (an index into
// FeatherScene::feathers) moved into the scene by `to_world`, an affine map whose
// linear part is a similarity: a rotation times a uniform scale, mirrored or not.
struct ScenePlacement {
  std::size_t feather = 0;
  glm::mat4 to_world{1.0f};
  int line = 0;
};

// The scene's own camera (`camera ...`); what is not given is the renderer's default.
struct SceneCamera {
  std::optional<glm::vec3> position, look_at, up;
  std::optional<float> fov_deg;
};

struct FeatherScene {
  std::vector<SceneFeather> feathers;
  std::vector<ScenePlacement> placements;
  SceneCamera camera;
  std::optional<std::string> lights;  // dome LEDs that are on: "all", "none", "1,5,12", "2-9"
};

// The linear part of an affine map taken apart: linear = scale x rotation, with
// rotation orthonormal (its determinant -1 when the map mirrors).
struct Similarity {
  glm::mat3 rotation{1.0f};
  float scale = 1;
  bool mirrored = false;
};
// The similarity `m`'s linear part is, or nothing when it is not one within a
// relative 1e-4 (shear, unequal scales, a zero or non-finite scale) or m's last
// row is not (0, 0, 0, 1).
std::optional<Similarity> similarity_of(const glm::mat4& m);

// What is wrong with `name` as a feather's name (1 to 64 letters, digits, '_', '-'
// and '.'), or "" when nothing is; the exporters name their objects by it too.
std::string scene_name_problem(std::string_view name);
// The word a feather's source has in the file: "fcurves", "preset" or "layout".
const char* to_string(SceneFeatherSource source);

// Throws plumage::Error for a scene the reader would refuse (no placement, an
// unknown feather index, a bad name, a transform that is not a similarity, ...).
void validate_scene(const FeatherScene& scene);

std::string format_fscene(const FeatherScene& scene);
// Writes atomically.
void write_fscene(const std::filesystem::path& path, const FeatherScene& scene);

// Parses text; `filename` is used in error messages. Throws plumage::Error at
// FILE:LINE:COL.
FeatherScene parse_fscene(std::string_view text, const std::string& filename = "<memory>");
FeatherScene read_fscene(const std::filesystem::path& path);

}  // namespace plumage
