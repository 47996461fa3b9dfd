#include "plumage/renderer/fibre_material.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/bspline.h"
#include "plumage/common/error.h"

namespace plumage {

AlbedoMap::AlbedoMap(const glm::vec3& constant) : constant_(constant) {}

AlbedoMap::AlbedoMap(const Albedo& albedo, const std::filesystem::path& base_dir, const Curve* shaft)
    : constant_(albedo.color), shaft_(albedo.shaft) {
  if (shaft_.size() > 1 && shaft && shaft->points.size() >= 4) {
    std::vector<glm::dvec3> cp;
    for (const ControlPoint& q : shaft->points) cp.push_back(q.p);
    shaft_arc_.emplace(BSpline3(std::move(cp)));
  }
  if (albedo.texture.empty()) return;
  std::filesystem::path path = albedo.texture;
  if (path.is_relative()) path = base_dir / path;
  const glm::vec2 size = albedo.rect_max - albedo.rect_min;
  if (!(size.x > 0 && size.y > 0))
    throw Error(Location{path.string()}, "the albedo texture's rect is empty (rect_max must exceed rect_min in x and y)");
  image_ = read_image(path);
  scale_ = albedo.scale;
  rect_min_ = albedo.rect_min;
  rect_max_ = albedo.rect_max;
}

glm::vec3 AlbedoMap::at(const glm::vec2& xy) const {
  if (image_.empty()) return constant_;
  // Texture (0,0) at rect_min, v growing toward rect_max.y; image row 0 is the top, i.e. rect_max.y.
  const glm::vec2 uv = (xy - rect_min_) / (rect_max_ - rect_min_);
  const float fx = std::clamp(uv.x, 0.0f, 1.0f) * float(image_.width) - 0.5f;
  const float fy = (1.0f - std::clamp(uv.y, 0.0f, 1.0f)) * float(image_.height) - 0.5f;
  const int x0 = std::clamp(int(std::floor(fx)), 0, image_.width - 1), x1 = std::min(x0 + 1, image_.width - 1);
  const int y0 = std::clamp(int(std::floor(fy)), 0, image_.height - 1), y1 = std::min(y0 + 1, image_.height - 1);
  const float tx = std::clamp(fx - float(x0), 0.0f, 1.0f), ty = std::clamp(fy - float(y0), 0.0f, 1.0f);
  const glm::vec3 top = glm::mix(image_.rgb(x0, y0), image_.rgb(x1, y0), tx);
  const glm::vec3 bottom = glm::mix(image_.rgb(x0, y1), image_.rgb(x1, y1), tx);
  return glm::clamp(glm::mix(top, bottom, ty), glm::vec3(0.0f), glm::vec3(1.0f)) * scale_;
}

glm::vec3 AlbedoMap::shaft_colour(float t) const {
  if (shaft_.size() == 1) return shaft_[0];
  if (!shaft_arc_ || !(shaft_arc_->length() > 0)) {  // nowhere to place them: their mean
    glm::vec3 sum(0.0f);
    for (const glm::vec3& c : shaft_) sum += c;
    return sum / float(shaft_.size());
  }
  return shaft_colour_at(shaft_, float(shaft_arc_->s_at(t) / shaft_arc_->length()));
}

glm::vec3 AlbedoMap::texel(int x, int y) const {
  return glm::clamp(image_.rgb(x, y), glm::vec3(0.0f), glm::vec3(1.0f)) * scale_;
}

FibreMaterial::FibreMaterial(const HairParams& params, AlbedoMap albedo, AlbedoMapping mapping)
    : params_(params), albedo_(std::move(albedo)), mapping_(mapping),
      constant_sigma_a_(sigma_a_from(albedo_->at({0, 0}))) {}

FibreMaterial::FibreMaterial(const HairParams& params) : params_(params), constant_sigma_a_(params.sigma_a) {}

glm::vec3 FibreMaterial::sigma_a_from(const glm::vec3& albedo) const {
  return mapping_ == AlbedoMapping::Layer ? sigma_a_from_layer_albedo(albedo, params_.eta)
                                          : sigma_a_from_albedo(albedo, params_.beta_n);
}

glm::vec3 photo_albedo_to_fibre(const glm::vec3& area_albedo, float coverage, int layers) {
  const glm::vec3 a = glm::clamp(area_albedo, glm::vec3(0.0f), glm::vec3(1.0f));
  // Each of the `layers` ribbons over the point returns its share t of the stack's
  // round trip, t^layers = A; within a ribbon a fraction `coverage` is fibre
  // (albedo f) and the rest passes the light, t = 1 - coverage (1 - f).
  const glm::vec3 t = layers > 1 ? glm::pow(a, glm::vec3(1.0f / float(layers))) : a;
  if (!(coverage > 0 && coverage < 1)) return t;
  return glm::vec3(1.0f) - (glm::vec3(1.0f) - t) / coverage;
}

void FibreMaterial::set_card(const glm::vec3& card, const CardResponse& response, bool absolute,
                             const glm::vec3& mean_gain, const CardResponse* down_response) {
  card_.emplace(response, card);
  if (down_response && down_response != &response)  // else at_down reads card_ through at()
    down_card_.emplace(*down_response, card);
  else
    down_card_.reset();
  texel_scale_ = absolute ? 1.0f / glm::max(card, glm::vec3(1e-3f)) : glm::vec3(1.0f);
  shift_ = glm::vec3(0.0f);
  if (mean_gain == glm::vec3(1.0f) || !albedo_ || !albedo_->textured()) return;
  glm::dvec3 sum(0.0);
  for (int y = 0; y < albedo_->height(); ++y)
    for (int x = 0; x < albedo_->width(); ++x) sum += glm::dvec3(albedo_->texel(x, y) * texel_scale_);
  shift_ = (mean_gain - 1.0f) * glm::vec3(sum / (double(albedo_->width()) * albedo_->height()));
}

glm::vec3 FibreMaterial::target(const glm::vec3& texel) const {
  return glm::max(texel * texel_scale_ + shift_, glm::vec3(0.0f));
}

InversionCounts FibreMaterial::count_inversion() const {
  InversionCounts n;
  if (!card_ || !albedo_ || !albedo_->textured()) return n;
  for (int y = 0; y < albedo_->height(); ++y)
    for (int x = 0; x < albedo_->width(); ++x) {
      const FibreColour fc = (*card_)(target(albedo_->texel(x, y)));
      ++n.texels;
      n.medulla += fc.medulla_sigma_s > 0.0f;
      n.clamped += fc.clamped;
    }
  return n;
}

HairParams FibreMaterial::at_shaft(const glm::vec3& p, float t) const {
  if (!albedo_ || !albedo_->has_shaft_colour()) return at(p);
  return from_albedo(albedo_->shaft_colour(t), 1.0f, 1, card_);
}

HairParams FibreMaterial::at_down(const glm::vec3& p) const {
  if (!down_card_ || !albedo_ || !albedo_->textured() || mapping_ != AlbedoMapping::Layer) return at(p);
  return from_albedo(albedo_->at({p.x, p.y}), 1.0f, 1, down_card_);
}

HairParams FibreMaterial::at(const glm::vec3& p, float coverage, int layers) const {
  if (albedo_ && albedo_->textured() && mapping_ == AlbedoMapping::Layer)
    return from_albedo(albedo_->at({p.x, p.y}), coverage, layers, card_);
  HairParams hp = params_;
  hp.sigma_a = albedo_ && albedo_->textured() ? sigma_a_from(albedo_->at({p.x, p.y})) : constant_sigma_a_;
  return hp;
}

HairParams FibreMaterial::from_albedo(glm::vec3 a, float coverage, int layers,
                                      const std::optional<CardCorrection>& card) const {
  HairParams hp = params_;
  if (mapping_ == AlbedoMapping::Layer && albedo_ && albedo_->textured()) {
    if (card) {
      const FibreColour fc = (*card)(target(a));
      a = fc.albedo;
      if (fc.medulla_sigma_s > 0.0f) {
        hp.medulla_ratio = kPhotoMedullaRatio;
        hp.medulla_sigma_s = glm::vec3(fc.medulla_sigma_s);
      }
    }
    hp.sigma_a = sigma_a_from(photo_albedo_to_fibre(a, coverage, layers));
    return hp;
  }
  hp.sigma_a = sigma_a_from(a);  // a constant albedo (or another mapping) is the fibres' own colour
  return hp;
}

}  // namespace plumage
