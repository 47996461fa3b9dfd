#include "plumage/renderer/dome_rig.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/install.h"
#include "plumage/common/json_file.h"

namespace plumage {
namespace {

glm::vec3 read_vec3_or_scalar(const nlohmann::json& j, const std::string& what, const std::string& file) {
  if (j.is_number()) return glm::vec3(j.get<float>());
  if (j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number())
    return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
  throw Error(Location{file}, "\"" + what + "\" must be a number or an array of 3 numbers");
}

}  // namespace

DomeRig parse_dome_rig(const std::string& text, const std::string& file) {
  const nlohmann::json j = parse_json(text, file);
  if (!j.is_object()) throw Error(Location{file}, "a light rig is a JSON object with \"leds\"");
  DomeRig rig;
  rig.name = j.value("name", std::string("rig"));
  if (j.contains("led_radius")) {
    if (!j["led_radius"].is_number()) throw Error(Location{file}, "\"led_radius\" must be a number (mm)");
    rig.led_radius = j["led_radius"].get<float>();
  }
  if (!(rig.led_radius > 0) || !std::isfinite(rig.led_radius))
    throw Error(Location{file}, "\"led_radius\" must be a positive number of mm");
  if (j.contains("intensity")) rig.intensity = read_vec3_or_scalar(j["intensity"], "intensity", file);
  if (!(rig.intensity.x >= 0 && rig.intensity.y >= 0 && rig.intensity.z >= 0) ||
      !std::isfinite(rig.intensity.x + rig.intensity.y + rig.intensity.z))
    throw Error(Location{file}, "\"intensity\" must be finite and non-negative (W/sr)");
  if (!j.contains("leds") || !j["leds"].is_array() || j["leds"].empty())
    throw Error(Location{file}, "\"leds\" must be a non-empty array of {\"position\": [x, y, z]}");
  for (std::size_t i = 0; i < j["leds"].size(); ++i) {
    const auto& led = j["leds"][i];
    const std::string what = "leds[" + std::to_string(i) + "].position";
    if (!led.is_object() || !led.contains("position"))
      throw Error(Location{file}, "\"" + what + "\" is missing");
    const glm::vec3 p = read_vec3_or_scalar(led["position"], what, file);
    if (!std::isfinite(p.x + p.y + p.z)) throw Error(Location{file}, "\"" + what + "\" is not finite");
    if (glm::length(p) <= rig.led_radius)
      throw Error(Location{file}, "\"" + what + "\" lies within one LED radius of the rig centre (the feather)");
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
