#include "plumage/renderer/dome_rig.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"

namespace plumage {
namespace {

Location location_of_byte(const std::string& text, std::size_t byte, const std::string& file) {
  int line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {file, line, col};
}

glm::vec3 read_vec3_or_scalar(const nlohmann::json& j, const std::string& what, const std::string& file) {
  if (j.is_number()) return glm::vec3(j.get<float>());
  if (j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number())
    return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
  throw Error(Location{file}, "\"" + what + "\" must be a number or an array of 3 numbers");
}

}  // namespace

DomeRig parse_dome_rig(const std::string& text, const std::string& file) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(location_of_byte(text, e.byte > 0 ? e.byte - 1 : 0, file),
                std::string("malformed JSON: ") + e.what());
  }
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

DomeRig read_dome_rig(const std::filesystem::path& path) {
  return parse_dome_rig(read_file(path), path.string());
}

std::vector<int> parse_light_selection(const std::string& spec, int count) {
  std::vector<int> out;
  if (spec == "all") {
    for (int i = 0; i < count; ++i) out.push_back(i);
    return out;
  }
  if (spec == "none" || spec.empty()) return out;
  std::stringstream ss(spec);
  std::string item;
  const std::string hint = "; give --lights all, none, or LED numbers 1.." + std::to_string(count) +
                           " such as 1,5,12 or 1-8";
  auto number = [&](const std::string& s) {
    std::size_t used = 0;
    int v = 0;
    try {
      v = std::stoi(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size()) throw Error("--lights: '" + s + "' is not a number" + hint);
    if (v < 1 || v > count) throw Error("--lights: LED " + s + " does not exist" + hint);
    return v - 1;
  };
  while (std::getline(ss, item, ',')) {
    const auto dash = item.find('-', 1);
    if (dash == std::string::npos) {
      out.push_back(number(item));
    } else {
      const int a = number(item.substr(0, dash)), b = number(item.substr(dash + 1));
      if (a > b) throw Error("--lights: range '" + item + "' runs backwards" + hint);
      for (int i = a; i <= b; ++i) out.push_back(i);
    }
  }
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
