#pragma once
// Pinhole perspective and orthographic cameras. By default the camera frames the
// feather from above (top view, looking down -Z with +Y up, DESIGN §3), fitting
// its bounds with a margin; an explicit look-at overrides the placement.
#include <optional>

#include <glm/glm.hpp>

#include "plumage/renderer/ray.h"
#include "plumage/renderer/scene.h"

namespace plumage {

enum class Projection { Perspective, Orthographic };

struct CameraSpec {
  Projection projection = Projection::Perspective;
  std::optional<glm::vec3> position;  // explicit look-at when set
  std::optional<glm::vec3> look_at;   // default: the feather's centre
  glm::vec3 up{0, 1, 0};
  float fov_deg = 30.0f;              // vertical field of view (perspective)
  float ortho_height = 0.0f;          // visible height in mm (orthographic); 0 = fit the feather
  float margin = 0.05f;               // auto-framing: fraction of the view left around the feather
};

class Camera {
 public:
  // Throws plumage::Error for a degenerate spec (position == look_at, up parallel
  // to the view direction, fov outside (0, 180), bad resolution).
  Camera(const CameraSpec& spec, int width, int height, const Bounds3f& feather_bounds);

  // Ray through film position (x, y) in pixels, (0,0) the top-left corner.
  Ray generate(float x, float y) const;

  int width() const { return width_; }
  int height() const { return height_; }
  const glm::vec3& position() const { return eye_; }
  const glm::vec3& forward() const { return fwd_; }
  // The smallest width a pixel covers anywhere in `box` (mm per pixel): for a
  // perspective camera the pixel's angle times the depth of the box's nearest point
  // in front of the camera (a box that reaches the eye's plane gives 0), for an
  // orthographic one the same everywhere. `--shading auto` compares it with a
  // feather's barbule period (shading_level.h).
  float pixel_footprint(const Bounds3f& box) const;

 private:
  Projection proj_;
  int width_, height_;
  glm::vec3 eye_, fwd_, right_, up_;
  float half_w_, half_h_;  // perspective: tan of half angles; orthographic: half extents (mm)
};

}  // namespace plumage
