#include "plumage/renderer/dome_rig.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/install.h"
#include "plumage/common/json_file.h"
#include "plumage/common/json_reader.h"

namespace plumage {
namespace {

// A number (the same for x, y and z) or [x, y, z].
glm::vec3 read_vec3_or_scalar(const JsonReader& j) {
  if (j.value().is_number()) return glm::vec3(float(j.number()));
  if (!j.value().is_array()) j.fail("expected a number or an array of 3 numbers");
  const auto v = j.numbers(3);
  return {float(v[0]), float(v[1]), float(v[2])};
}

}  // namespace

DomeRig parse_dome_rig(const std::string& text, const std::string& file) {
  const nlohmann::json doc = parse_json(text, file);
  const JsonReader top(doc, file, "see docs/rendering.md, \"The dome rig\"");
  top.expect_object();
  DomeRig rig;
  rig.name = "rig";
  if (const auto name = top.find("name")) rig.name = name->string();
  if (const auto radius = top.find("led_radius")) {
    rig.led_radius = float(radius->number());
    if (!(rig.led_radius > 0)) radius->fail("expected a positive number of mm");
  }
  if (const auto intensity = top.find("intensity")) {
    rig.intensity = read_vec3_or_scalar(*intensity);
    if (!(rig.intensity.x >= 0 && rig.intensity.y >= 0 && rig.intensity.z >= 0))
      intensity->fail("expected finite, non-negative values (W/sr)");
  }
  for (const JsonReader& led : top.member("leds").elements(0, 1)) {
    const JsonReader position = led.member("position");
    const glm::vec3 p = read_vec3_or_scalar(position);
    if (!std::isfinite(p.x + p.y + p.z)) position.fail("is not finite");
    if (glm::length(p) <= rig.led_radius) position.fail("lies within one LED radius of the rig centre (the feather)");
    rig.leds.push_back(p);
  }
  return rig;
}

std::filesystem::path default_rig_path() { return data_dir() / "rigs" / "dome25.json"; }

DomeRig read_dome_rig(const std::filesystem::path& path) {
  return parse_dome_rig(read_json_text(path), path.string());
}

std::vector<std::pair<int, int>> light_ranges(const std::string& spec, int count) {
  if (spec == "all") return {{1, count}};
  if (spec == "none" || spec.empty()) return {};
  const std::string hint = "; give --lights all, none, or LED numbers" +
                           (count == std::numeric_limits<int>::max() ? std::string() : " 1.." + std::to_string(count)) +
                           " such as 1,5,12 or 1-8";
  auto number = [&](const std::string& s) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
      throw Error("--lights: '" + s + "' is not an LED number" + hint);
    const int v = std::stoi(s);
    if (v < 1 || v > count) throw Error("--lights: LED " + s + " does not exist" + hint);
    return v;
  };
  std::vector<std::pair<int, int>> out;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto dash = item.find('-', 1);
    if (dash == std::string::npos) {
      const int a = number(item);
      out.emplace_back(a, a);
    } else {
      const int a = number(item.substr(0, dash)), b = number(item.substr(dash + 1));
      if (a > b) throw Error("--lights: range '" + item + "' runs backwards" + hint);
      out.emplace_back(a, b);
    }
  }
  if (spec.back() == ',') throw Error("--lights: '" + spec + "' ends with a comma" + hint);
  return out;
}

std::vector<int> parse_light_selection(const std::string& spec, int count) {
  std::vector<int> out;
  for (const auto& [a, b] : light_ranges(spec, count))
    for (int i = a; i <= b; ++i) out.push_back(i - 1);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<SphereLight> dome_lights(const DomeRig& rig, const std::vector<int>& selection, const glm::vec3& centre) {
  std::vector<SphereLight> lights;
  const glm::vec3 L = SphereLight::radiance_for_intensity(rig.intensity, rig.led_radius);
  for (int i : selection) lights.push_back({centre + rig.leds.at(std::size_t(i)), rig.led_radius, L});
  return lights;
}

}  // namespace plumage
