#pragma once
// What a fibre hit is made of: the hair BCSDF's roughness, tilt and index from the
// command line, and an absorption sigma_a that comes from the feather's albedo
// (constant, or its texture through the rect mapping; AlbedoMapping says how) or
// is given directly (e.g. from melanin concentrations).
#include <filesystem>
#include <optional>

#include <glm/glm.hpp>

#include "plumage/common/bspline.h"
#include "plumage/common/feather.h"
#include "plumage/common/image.h"
#include "plumage/renderer/card_response.h"
#include "plumage/renderer/hair_bcsdf.h"

namespace plumage {

// The feather's albedo as a function of position in the XY plane.
class AlbedoMap {
 public:
  // A texture path is resolved against `base_dir` (the curve file's folder); throws
  // plumage::Error naming the texture when it cannot be read or the rect is empty.
  // `shaft`, the feather's shaft curve, places the shaft's colours along it (a
  // shaft colour given at several stations; without it they are averaged).
  AlbedoMap(const Albedo& albedo, const std::filesystem::path& base_dir, const Curve* shaft = nullptr);
  explicit AlbedoMap(const glm::vec3& constant = glm::vec3(0.5f));

  bool textured() const { return !image_.empty(); }
  // Whether the feather's shaft has a colour of its own (Albedo::shaft).
  bool has_shaft_colour() const { return !shaft_.empty(); }
  // The shaft's own colour where the shaft curve's B-spline parameter is t (in
  // [0, 1], root first): at that fraction of its arc length (shaft_colour_at).
  // Needs has_shaft_colour().
  glm::vec3 shaft_colour(float t) const;
  // Linear RGB at a point (the texture is clamped at its edges; bilinear), times the
  // albedo's scale: in [0, scale].
  glm::vec3 at(const glm::vec2& xy) const;
  // The texture's texel (x, y) as at() reads it (clamped to [0, 1], times the scale).
  glm::vec3 texel(int x, int y) const;
  int width() const { return image_.width; }
  int height() const { return image_.height; }

 private:
  glm::vec3 constant_;
  Image image_;
  glm::vec2 rect_min_{0}, rect_max_{1};
  float scale_ = 1.0f;  // Albedo::scale
  std::vector<glm::vec3> shaft_;
  std::optional<ArcLengthTable> shaft_arc_;  // the shaft curve's, when its colour changes along it
};

// How an albedo becomes an absorption coefficient (docs/hair-bcsdf.md).
enum class AlbedoMapping {
  Layer,       // one layer of fibres over a white card looks `albedo` times the card (default)
  Chiang2016,  // the albedo of a dense mass of hair under multiple scattering (Chiang et al. 2016 eq. 9)
};

// The fibre albedo f that makes a point of a vane `layers` ribbons deep, each
// ribbon a fraction `coverage` fibre and the rest open, return the area albedo A
// measured on a photo: each ribbon's round trip t = 1 - coverage (1 - f), and
// t^layers = A (docs/hair-bcsdf.md, "A photo's albedo over overlapping ribbons").
// A is clamped to [0, 1]; the result may be <= 0 where open gaps alone are
// brighter than A (sigma_a_from_* clamp it to their least albedo).
glm::vec3 photo_albedo_to_fibre(const glm::vec3& area_albedo, float coverage, int layers);

// How an albedo texture's texels come through the card response's inversion
// (CardCorrection): how many, how many were given a medulla (paler than clear
// fibres show over the card), and how many were clamped (beyond every fibre the
// table holds).
struct InversionCounts {
  long texels = 0, medulla = 0, clamped = 0;
};

class FibreMaterial {
 public:
  // Absorption from the albedo map.
  FibreMaterial(const HairParams& params, AlbedoMap albedo, AlbedoMapping mapping = AlbedoMapping::Layer);
  // Absorption fixed to params.sigma_a everywhere.
  explicit FibreMaterial(const HairParams& params);

  // The fibre's parameters at p. A texture (taken from a photo) is an area mean
  // over a vane that may be several ribbons deep and whose ribbons may be partly
  // open, so with AlbedoMapping::Layer the fibre takes photo_albedo_to_fibre(A,
  // coverage, layers): `coverage`, the fraction of a ribbon that its rami and
  // barbules cover (1 in hair mode), and `layers`, how many ribbons lie over p
  // (Scene::ribbon_layers). Then the stack over p returns A. A constant albedo (a
  // preset's) is the fibres' own colour and is used as it is.
  HairParams at(const glm::vec3& p, float coverage = 1.0f, int layers = 1) const;
  // The shaft's fibre at p, where the shaft curve's parameter is t
  // (Scene::curve_parameter): the feather's shaft colour there (Albedo::shaft)
  // where it has one, through the same card correction, one layer deep; else at(p).
  HairParams at_shaft(const glm::vec3& p, float t) const;
  // A down barb's fibre at p (CurveKind::Down): the albedo there, one layer deep,
  // through the down barbs' card correction (set_card's `down_response`: a down
  // barb is a fibre, shaded alike in every mode), else the one of at().
  HairParams at_down(const glm::vec3& p) const;

  // The texture is a photo's, of a feather lying on the card it lies on in the
  // render (albedo `card`): relative to that card (a light background, the paper
  // divided out), or with `absolute` the photo's own colour (a dark background),
  // which is divided by the card's colour first. Before the mapping each texel
  // becomes the fibre of CardCorrection(response, card): an albedo, and for texels
  // paler than clear fibres can look, a medulla (ratio kPhotoMedullaRatio) that
  // scatters; so the vane looks as the photo's does although part of its light
  // never reaches the card (card_response.h).
  // `mean_gain` (photo-to-feather's colour calibration, colour_calibration.h)
  // moves every texel by (mean_gain - 1) times the texture's mean, per channel, so
  // the mean is mean_gain times itself and the detail stays: what the table misses
  // for a rendered feather is mostly light that never reaches the card, the same
  // on a dark texel as on a pale one, so a shift, not a scale, corrects it (a
  // texel shifted below 0 is taken as 0). 1 leaves the texels as they are.
  // `down_response`, when given, is the card response the down barbs' texels go
  // through (at_down); else, or when it is `response` itself, `response`.
  void set_card(const glm::vec3& card, const CardResponse& response, bool absolute = false,
                const glm::vec3& mean_gain = glm::vec3(1.0f), const CardResponse* down_response = nullptr);

  // Every texel of the albedo texture through the card correction set_card gave,
  // as at() takes it; all zero without a texture or a card.
  InversionCounts count_inversion() const;

 private:
  glm::vec3 sigma_a_from(const glm::vec3& albedo) const;
  // A texel's (or the shaft's) albedo as the card correction takes it: scaled to the
  // card, shifted by the calibration.
  glm::vec3 target(const glm::vec3& texel) const;
  // The fibre for a texel's (or the shaft's) albedo `a`: a photo's texture through
  // the card correction and the layer mapping, else a's absorption.
  HairParams from_albedo(glm::vec3 a, float coverage, int layers, const std::optional<CardCorrection>& card) const;

  HairParams params_;
  std::optional<AlbedoMap> albedo_;
  AlbedoMapping mapping_ = AlbedoMapping::Layer;
  glm::vec3 constant_sigma_a_;
  std::optional<CardCorrection> card_, down_card_;
  glm::vec3 texel_scale_{1.0f};  // 1 / the card per channel for an absolute texture
  glm::vec3 shift_{0.0f};        // set_card's mean_gain as a shift of every texel
};

}  // namespace plumage
