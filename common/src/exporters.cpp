// Exporters to pbrt-v4, pbrt-v3, Mitsuba 3 and Wavefront OBJ (exporters.h).
//
// All four take uniform cubic B-spline control points as they are (pbrt's and
// Mitsuba's "bspline" curves and OBJ's `cstype bspline` with uniform knots are the
// same curve as ours). What they cannot hold is said in a comment in the output.
#include "plumage/common/exporters.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <type_traits>

#include "float_text.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/scene_format.h"

namespace plumage {

using detail::append_float;
using detail::append_vec3;
using detail::append_int;

namespace {

struct FormatName {
  ExportFormat format;
  const char* name;
  const char* extension;
};
constexpr FormatName kFormats[] = {{ExportFormat::Fcurves, "fcurves", ".fcurves"},
                                   {ExportFormat::Pbrt, "pbrt", ".pbrt"},
                                   {ExportFormat::PbrtV3, "pbrt-v3", ".pbrt"},
                                   {ExportFormat::Mitsuba, "mitsuba", ".txt"},
                                   {ExportFormat::Obj, "obj", ".obj"},
                                   {ExportFormat::Blender, "blender", ".py"}};

// Value of a uniform cubic B-spline at joint k (0 <= k <= n-3; joint 0 is the
// start, joint n-3 the end), where the segment basis is (1, 4, 1) / 6. In double,
// so control values near the float limit do not overflow on the way.
template <class T>
auto at_joint(const std::vector<ControlPoint>& cp, std::size_t k, T ControlPoint::*field) {
  using D = std::conditional_t<std::is_same_v<T, float>, double, glm::dvec3>;
  return (D(cp[k].*field) + 4.0 * D(cp[k + 1].*field) + D(cp[k + 2].*field)) / 6.0;
}

// Numbers written for other programs stay finite: a float-range feather can
// still give a camera distance or width beyond the float range.
float finite_float(double v) {
  constexpr double kMax = std::numeric_limits<float>::max();
  return static_cast<float>(std::clamp(v, -kMax, kMax));
}
glm::vec3 finite_vec3(const glm::dvec3& v) { return {finite_float(v.x), finite_float(v.y), finite_float(v.z)}; }

// A string for a pbrt or OBJ comment line: one line, printable.
std::string one_line(const std::string& s) {
  std::string r = s;
  for (char& c : r)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return r;
}

void append_provenance_comment(std::string& out, const Feather& f, const char* comment) {
  out += comment;
  out += " Plumage feather: ";
  append_int(out, f.count(CurveKind::Shaft));
  out += " shaft, ";
  append_int(out, f.count(CurveKind::Barb));
  out += " barbs, ";
  const std::size_t down = f.count(CurveKind::Down);
  if (down) {
    append_int(out, down);
    out += " down barbs, ";
  }
  append_int(out, f.num_control_points());
  out += " control points; units mm\n";
  if (down && f.down_cover != 1.0f) {
    out += comment;
    out += " down barbs: round curves the reach of their barbules, which Plumage fills ";
    append_float(out, f.down_cover);
    out += " of (down cover); drawn here whole\n";
  }
  if (!f.provenance.source.empty() || f.provenance.seed) {
    out += comment;
    out += " source: ";
    out += one_line(f.provenance.source.empty() ? "(unknown)" : f.provenance.source);
    if (f.provenance.seed) {
      out += ", seed ";
      append_int(out, *f.provenance.seed);
    }
    out += '\n';
  }
}

enum class PbrtVersion { V3, V4 };

void append_pbrt_floats(std::string& out, const char* type_name, std::initializer_list<float> values) {
  out += " \"";
  out += type_name;
  out += "\" [";
  for (float v : values) {
    out += ' ';
    append_float(out, finite_float(v));
  }
  out += " ]";
}

void append_pbrt_rgb(std::string& out, const char* name, const glm::vec3& c) {
  append_pbrt_floats(out, name, {c.x, c.y, c.z});
}

// Barbs as pbrt's "flat" curves: ribbons that always face the ray, as hair mode
// draws them; the shaft and down barbs as "cylinder"s, as plumage's round fibres.
void append_pbrt_curve(std::string& out, const Feather& f, const Curve& c, PbrtVersion v) {
  const auto& cp = c.points;
  const std::size_t segments = cp.size() - 3;
  out += "Shape \"curve\" \"string basis\" [ \"bspline\" ] \"string type\" [ \"";
  out += c.kind == CurveKind::Barb ? "flat" : "cylinder";
  out += v == PbrtVersion::V4 ? "\" ]\n  \"point3 P\" [" : "\" ]\n  \"point P\" [";
  for (const ControlPoint& p : cp) {
    out += ' ';
    append_vec3(out, p.p);
  }
  // pbrt interpolates width linearly from the curve's start to its end; plumage's
  // radius is a B-spline per control point, so its end values are used (exact for
  // a barb drawn at its vane's constant ribbon width). A barb's tip taper
  // (kBarbTipTaper) would narrow the whole curve that way, so a barb keeps its
  // base width to the tip: pbrt draws square ribbon ends where plumage tapers.
  std::vector<ControlPoint> drawn(cp);
  const std::vector<float> radii = render_radii(f, c);
  for (std::size_t i = 0; i < drawn.size(); ++i) drawn[i].radius = radii[i];
  const float end_width = c.kind == CurveKind::Barb ? at_joint(drawn, 0, &ControlPoint::radius)
                                                    : at_joint(drawn, segments, &ControlPoint::radius);
  out += " ]\n ";
  append_pbrt_floats(out, "float width0", {finite_float(2 * at_joint(drawn, 0, &ControlPoint::radius))});
  append_pbrt_floats(out, "float width1", {finite_float(2 * end_width)});
  out += '\n';
}

// The comment lines that say which plumage render this scene stands for.
void append_scene_comment(std::string& out, const ExportScene& s, const char* comment) {
  out += comment;
  out += " What `plumage render` renders in ";
  out += one_line(s.shading);
  out += " mode: its camera, lights, card, hair material and depth.\n";
  if (s.shading != "hair") {
    out += comment;
    out += " plumage's ";
    out += one_line(s.shading);
    out += " mode (rami and barbules inside each barb) has no counterpart here: the\n";
    out += comment;
    out += " barbs are hair fibres of the same width, as plumage's hair mode draws them.\n";
  }
  if (!s.material_note.empty()) {
    out += comment;
    out += ' ';
    out += one_line(s.material_note);
    out += '\n';
  }
}

// The scene around the feathers: comments, camera, sampler, film, WorldBegin,
// lights and card. `what` is the provenance comment (one feather's, or the scene's).
void append_pbrt_head(std::string& out, const std::string& what, const ExportScene& s, PbrtVersion v) {
  const bool v4 = v == PbrtVersion::V4;
  out += v4 ? "# pbrt-v4 scene" : "# pbrt-v3 scene";
  out += " written by `plumage export`. Curves are uniform cubic B-splines in mm.\n";
  out += what;
  append_scene_comment(out, s, "#");
  out += "# Mirror x so the image shows the dorsal side as seen from +Z (pbrt's LookAt is left-handed).\n";
  out += "Scale -1 1 1\nLookAt ";
  append_vec3(out, finite_vec3(s.camera.eye));
  out += "  ";
  append_vec3(out, finite_vec3(s.camera.look_at));
  out += "  ";
  append_vec3(out, finite_vec3(s.camera.up));
  out += "\n# pbrt's fov spans the image's shorter side; plumage's vertical fov is ";
  append_float(out, s.camera.fov_deg);
  out += ".\nCamera \"perspective\"";
  append_pbrt_floats(out, "float fov", {pbrt_fov_deg(s)});
  out += '\n';
  out += v4 ? "Sampler \"zsobol\"" : "Sampler \"halton\"";
  out += " \"integer pixelsamples\" [ ";
  append_int(out, s.spp);
  out += " ]\n";
  out += "# maxdepth counts scattering events as plumage's --max-depth does (1 = direct light only).\n";
  out += v4 ? "Integrator \"volpath\"" : "Integrator \"path\"";
  out += " \"integer maxdepth\" [ ";
  append_int(out, s.max_depth);
  out += " ]\n";
  out += "PixelFilter \"box\"\n";  // plumage averages samples spread uniformly over the pixel
  out += v4 ? "Film \"rgb\" \"string filename\" [ \"" : "Film \"image\" \"string filename\" [ \"";
  out += one_line(s.image_filename);
  out += "\" ]\n  \"integer xresolution\" [ ";
  append_int(out, s.width);
  out += " ] \"integer yresolution\" [ ";
  append_int(out, s.height);
  out += " ]\n\nWorldBegin\n";
  if (!s.lights.empty())
    out += "# The dome's LEDs: spheres of uniform radiance, as plumage's sphere lights.\n";
  for (const ExportSphereLight& l : s.lights) {
    out += "AttributeBegin\n  AreaLightSource \"diffuse\"";
    append_pbrt_rgb(out, "rgb L", l.radiance);
    out += "\n  Translate ";
    append_vec3(out, finite_vec3(l.centre));
    out += "\n  Shape \"sphere\"";
    append_pbrt_floats(out, "float radius", {l.radius});
    out += "\nAttributeEnd\n";
  }
  if (s.environment) {
    out += "LightSource \"infinite\"";
    append_pbrt_rgb(out, "rgb L", *s.environment);
    out += '\n';
  }
  if (s.card) {
    const ExportCard& c = *s.card;
    out += "# The backdrop card: a diffuse square under the feather.\nAttributeBegin\n  ";
    out += v4 ? "Material \"diffuse\"" : "Material \"matte\"";
    append_pbrt_rgb(out, v4 ? "rgb reflectance" : "rgb Kd", c.albedo);
    out += "\n  Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n ";
    const float h = c.half_side;
    const glm::dvec3 o(c.centre);
    std::initializer_list<float> corners = {
        finite_float(o.x - h), finite_float(o.y - h), finite_float(o.z), finite_float(o.x + h), finite_float(o.y - h),
        finite_float(o.z),     finite_float(o.x + h), finite_float(o.y + h), finite_float(o.z), finite_float(o.x - h),
        finite_float(o.y + h), finite_float(o.z)};
    append_pbrt_floats(out, v4 ? "point3 P" : "point P", corners);
    out += "\nAttributeEnd\n";
  }
}

// Chiang et al. 2016 hair BSDF with plumage's absorption (per unit radius in both).
void append_pbrt_material(std::string& out, const ExportMaterial& m) {
  out += "# pbrt's alpha has the opposite sign to plumage's (plumage alpha = ";
  append_float(out, m.alpha_deg);
  out += " is pbrt alpha = ";
  append_float(out, -m.alpha_deg);
  out += ").\nMaterial \"hair\"";
  append_pbrt_rgb(out, "rgb sigma_a", m.sigma_a);
  append_pbrt_floats(out, "float beta_m", {m.beta_m});
  append_pbrt_floats(out, "float beta_n", {m.beta_n});
  append_pbrt_floats(out, "float alpha", {-m.alpha_deg});
  append_pbrt_floats(out, "float eta", {m.eta});
  out += '\n';
}

std::string format_pbrt(const Feather& f, const ExportScene& s, PbrtVersion v) {
  validate_feather(f);
  std::string out;
  out.reserve(4096 + f.num_control_points() * 48);
  std::string what;
  append_provenance_comment(what, f, "#");
  append_pbrt_head(out, what, s, v);
  out += "\nAttributeBegin\n";
  append_pbrt_material(out, s.material);
  for (const Curve& c : f.curves) append_pbrt_curve(out, f, c, v);
  out += "AttributeEnd\n";
  if (v == PbrtVersion::V3) out += "WorldEnd\n";
  return out;
}

void validate_instances(const ExportInstances& in) {
  if (in.feathers.empty() || in.placements.empty()) throw Error("a scene to export needs a feather and a placement");
  for (std::size_t i = 0; i < in.feathers.size(); ++i) {
    const ExportFeather& f = in.feathers[i];
    if (!scene_name_problem(f.name).empty())
      throw Error("feather " + std::to_string(i) + ": name '" + one_line(f.name) +
                  "' is not 1-64 letters, digits, '_', '-' or '.'");
    for (std::size_t j = 0; j < i; ++j)
      if (in.feathers[j].name == f.name) throw Error("feather name '" + f.name + "' is given twice");
    if (!f.feather) throw Error("feather '" + f.name + "' has no curves");
    validate_feather(*f.feather);
  }
  for (std::size_t i = 0; i < in.placements.size(); ++i) {
    const ExportPlacement& p = in.placements[i];
    if (p.feather >= in.feathers.size())
      throw Error("placement " + std::to_string(i) + " names feather " + std::to_string(p.feather) + " of " +
                  std::to_string(in.feathers.size()));
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(p.to_world[c][r]))
          throw Error("placement " + std::to_string(i) + " has a non-finite transform");
  }
}

// The comment lines that say what a scene of placed feathers holds.
std::string instances_comment(const ExportInstances& in, const char* comment) {
  std::size_t barbs = 0;
  for (const ExportPlacement& p : in.placements) barbs += in.feathers[p.feather].feather->count(CurveKind::Barb);
  std::string out = comment;
  out += " Plumage scene: ";
  append_int(out, in.feathers.size());
  out += " distinct feathers, ";
  append_int(out, in.placements.size());
  out += " placements, ";
  append_int(out, barbs);
  out += " barbs over all placements; units mm\n";
  return out;
}

std::string format_pbrt(const ExportInstances& in, const ExportScene& s, PbrtVersion v) {
  validate_instances(in);
  std::string out;
  append_pbrt_head(out, instances_comment(in, "#"), s, v);
  out += "# Each distinct feather once, as an object with its own material; each placement an instance.\n";
  for (const ExportFeather& ef : in.feathers) {
    out += "\n";
    append_provenance_comment(out, *ef.feather, "#");
    out += "ObjectBegin \"" + ef.name + "\"\n";
    append_pbrt_material(out, ef.material);
    for (const Curve& c : ef.feather->curves) append_pbrt_curve(out, *ef.feather, c, v);
    out += "ObjectEnd\n";
  }
  out += "\n# Placements: Transform lists the 4x4 matrix column by column, as pbrt reads it.\n";
  for (const ExportPlacement& p : in.placements) {
    out += "AttributeBegin\n  Transform [";
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) {
        out += ' ';
        append_float(out, finite_float(p.to_world[col][row]));
      }
    out += " ]\n  ObjectInstance \"" + in.feathers[p.feather].name + "\"\nAttributeEnd\n";
  }
  if (v == PbrtVersion::V3) out += "WorldEnd\n";
  return out;
}

// --------------------------------------------------------------- Mitsuba ---

std::string xml_escaped(const std::string& s) {
  std::string r;
  for (char c : one_line(s)) {
    switch (c) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      default: r += c;
    }
  }
  return r;
}

// "x, y, z" for a Mitsuba value attribute.
std::string mitsuba_triple(const glm::vec3& v) {
  std::string r;
  append_float(r, finite_float(v.x));
  r += ", ";
  append_float(r, finite_float(v.y));
  r += ", ";
  append_float(r, finite_float(v.z));
  return r;
}

void append_xml_float(std::string& out, const char* indent, const char* name, float v) {
  out += indent;
  out += "<float name=\"";
  out += name;
  out += "\" value=\"";
  append_float(out, finite_float(v));
  out += "\"/>\n";
}

void append_xml_int(std::string& out, const char* indent, const char* name, int v) {
  out += indent;
  out += "<integer name=\"";
  out += name;
  out += "\" value=\"";
  append_int(out, v);
  out += "\"/>\n";
}

// XML comments may not hold "--".
std::string xml_comment_text(const std::string& s) {
  std::string r = one_line(s);
  for (std::size_t i; (i = r.find("--")) != std::string::npos;) r.replace(i, 2, "- ");
  return r;
}

}  // namespace

const char* to_string(ExportFormat f) {
  for (const FormatName& n : kFormats)
    if (n.format == f) return n.name;
  return "?";
}

const char* default_extension(ExportFormat f) {
  for (const FormatName& n : kFormats)
    if (n.format == f) return n.extension;
  return "";
}

ExportFormat parse_export_format(std::string_view name) {
  std::string known;
  for (const FormatName& n : kFormats) {
    if (name == n.name) return n.format;
    known += known.empty() ? "" : ", ";
    known += n.name;
  }
  throw Error("unknown export format '" + std::string(name) + "': use one of " + known);
}

float pbrt_fov_deg(const ExportScene& s) {
  if (s.width >= s.height) return s.camera.fov_deg;
  const double tan_half_y = std::tan(0.5 * double(s.camera.fov_deg) * std::numbers::pi / 180.0);
  const double tan_half_x = tan_half_y * double(s.width) / double(s.height);
  return float(2.0 * std::atan(tan_half_x) * 180.0 / std::numbers::pi);
}

std::string format_pbrt_v4(const Feather& f, const ExportScene& s) { return format_pbrt(f, s, PbrtVersion::V4); }
std::string format_pbrt_v3(const Feather& f, const ExportScene& s) { return format_pbrt(f, s, PbrtVersion::V3); }
std::string format_pbrt_v4(const ExportInstances& in, const ExportScene& s) { return format_pbrt(in, s, PbrtVersion::V4); }
std::string format_pbrt_v3(const ExportInstances& in, const ExportScene& s) { return format_pbrt(in, s, PbrtVersion::V3); }

std::string format_mitsuba_curves(const Feather& f) {
  validate_feather(f);
  // Mitsuba's loader takes no comments: numbers only, a blank line ends a curve.
  std::string out;
  out.reserve(f.num_control_points() * 40);
  bool first = true;
  for (const Curve& c : f.curves) {
    if (!first) out += '\n';
    first = false;
    const std::vector<float> radii = render_radii(f, c);
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      append_vec3(out, c.points[i].p);
      out += ' ';
      append_float(out, radii[i]);
      out += '\n';
    }
  }
  return out;
}

namespace {

// The XML up to the feathers: the comment, integrator, sensor, lights and card.
// `what` is the provenance comment (one feather's, or the scene's).
std::string mitsuba_head(const std::string& what, const ExportScene& s) {
  std::string head = what;
  append_scene_comment(head, s, "   ");
  head += "    Mitsuba's bsplinecurve is a round tube: the barbs keep plumage's width, but plumage's\n"
          "    hair mode draws them as flat ribbons facing the ray (docs/exporters.md).\n";
  std::string out = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- Mitsuba 3 scene written by `plumage export`. Units mm.\n";
  for (std::size_t i = 0; i < head.size();) {
    const std::size_t e = head.find('\n', i);
    out += xml_comment_text(head.substr(i, e - i));
    out += '\n';
    i = e + 1;
  }
  out += "-->\n<scene version=\"3.0.0\">\n";
  out += "    <!-- max_depth counts the camera segment: plumage's max depth + 1 (2 = direct light only). -->\n";
  out += "    <integrator type=\"path\">\n";
  append_xml_int(out, "        ", "max_depth", s.max_depth + 1);
  out += "    </integrator>\n    <sensor type=\"perspective\">\n";
  append_xml_float(out, "        ", "fov", s.camera.fov_deg);
  out += "        <string name=\"fov_axis\" value=\"y\"/>\n        <transform name=\"to_world\">\n";
  out += "            <lookat origin=\"" + mitsuba_triple(s.camera.eye) + "\" target=\"" +
         mitsuba_triple(s.camera.look_at) + "\" up=\"" + mitsuba_triple(s.camera.up) + "\"/>\n";
  out += "        </transform>\n        <sampler type=\"independent\">\n";
  append_xml_int(out, "            ", "sample_count", s.spp);
  out += "        </sampler>\n        <film type=\"hdrfilm\">\n";
  append_xml_int(out, "            ", "width", s.width);
  append_xml_int(out, "            ", "height", s.height);
  out += "            <rfilter type=\"box\"/>\n        </film>\n    </sensor>\n";
  for (const ExportSphereLight& l : s.lights) {
    out += "    <shape type=\"sphere\">\n        <point name=\"center\" value=\"" + mitsuba_triple(l.centre) + "\"/>\n";
    append_xml_float(out, "        ", "radius", l.radius);
    out += "        <emitter type=\"area\"><rgb name=\"radiance\" value=\"" + mitsuba_triple(l.radiance) +
           "\"/></emitter>\n    </shape>\n";
  }
  if (s.environment)
    out += "    <emitter type=\"constant\"><rgb name=\"radiance\" value=\"" + mitsuba_triple(*s.environment) +
           "\"/></emitter>\n";
  if (s.card) {
    // Mitsuba's rectangle spans [-1,1]^2 in z = 0, facing +Z.
    const ExportCard& c = *s.card;
    out += "    <shape type=\"rectangle\">\n        <transform name=\"to_world\">\n";
    out += "            <scale value=\"" + mitsuba_triple({c.half_side, c.half_side, 1.0f}) + "\"/>\n";
    out += "            <translate value=\"" + mitsuba_triple(c.centre) + "\"/>\n        </transform>\n";
    out += "        <bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"" + mitsuba_triple(c.albedo) +
           "\"/></bsdf>\n    </shape>\n";
  }
  return out;
}

// A bsplinecurve shape loading `curves_filename` with the hair BSDF of `m`,
// indented by `in` (four spaces at the scene's top level).
std::string mitsuba_curves_shape(const std::string& curves_filename, const ExportMaterial& m, const std::string& in) {
  std::string out = in + "<shape type=\"bsplinecurve\">\n" + in + "    <string name=\"filename\" value=\"" +
                    xml_escaped(curves_filename) + "\"/>\n";
  out += in + "    <!-- Chiang et al. 2016 with plumage's sigma_a (per unit radius); scale_tilt is pbrt's alpha\n" + in +
         "         (Mitsuba's hair BSDF follows pbrt-v3): minus plumage's alpha. -->\n";
  out += in + "    <bsdf type=\"hair\">\n";
  out += in + "        <rgb name=\"sigma_a\" value=\"" + mitsuba_triple(m.sigma_a) + "\"/>\n";
  const std::string deeper = in + "        ";
  append_xml_float(out, deeper.c_str(), "longitudinal_roughness", m.beta_m);
  append_xml_float(out, deeper.c_str(), "azimuthal_roughness", m.beta_n);
  append_xml_float(out, deeper.c_str(), "scale_tilt", -m.alpha_deg);
  append_xml_float(out, deeper.c_str(), "int_ior", m.eta);
  append_xml_float(out, deeper.c_str(), "ext_ior", 1.0f);
  out += in + "    </bsdf>\n" + in + "</shape>\n";
  return out;
}

}  // namespace

std::string format_mitsuba_scene(const Feather& f, const ExportScene& s, const std::string& curves_filename) {
  validate_feather(f);
  std::string what;
  append_provenance_comment(what, f, "   ");
  return mitsuba_head(what, s) + mitsuba_curves_shape(curves_filename, s.material, "    ") + "</scene>\n";
}

std::string format_mitsuba_scene(const ExportInstances& in, const ExportScene& s,
                                 const std::vector<std::string>& curve_files) {
  validate_instances(in);
  if (curve_files.size() != in.feathers.size())
    throw Error("a Mitsuba scene of " + std::to_string(in.feathers.size()) + " feathers needs as many curve files");
  std::string out = mitsuba_head(instances_comment(in, "   "), s);
  out += "    <!-- Each distinct feather once, a shapegroup with its own material; each placement an instance\n"
         "         (its to_world matrix row by row). -->\n";
  for (std::size_t i = 0; i < in.feathers.size(); ++i) {
    out += "    <shape type=\"shapegroup\" id=\"feather_" + in.feathers[i].name + "\">\n";
    out += mitsuba_curves_shape(curve_files[i], in.feathers[i].material, "        ");
    out += "    </shape>\n";
  }
  for (const ExportPlacement& p : in.placements) {
    out += "    <shape type=\"instance\">\n        <ref id=\"feather_" + in.feathers[p.feather].name + "\"/>\n";
    out += "        <transform name=\"to_world\"><matrix value=\"";
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col) {
        if (row || col) out += ' ';
        append_float(out, finite_float(p.to_world[col][row]));
      }
    out += "\"/></transform>\n    </shape>\n";
  }
  out += "</scene>\n";
  return out;
}

namespace {

// The curves of `f` as OBJ objects named `prefix` + shaft / barb_SIDE_K, their
// control points carried by `to_world`; vertices numbered from `next_vertex`.
void append_obj_curves(std::string& out, const Feather& f, const std::string& prefix, const glm::mat4& to_world,
                       std::size_t& next_vertex) {
  std::size_t barb = 0;
  const bool identity = to_world == glm::mat4(1.0f);
  for (const Curve& c : f.curves) {
    const std::size_t n = c.points.size();
    out += "o " + prefix;
    if (c.kind == CurveKind::Shaft) {
      out += "shaft\n";
    } else {
      out += c.kind == CurveKind::Down ? "down_" : "barb_";
      out += to_string(c.side);
      out += '_';
      append_int(out, barb++);
      out += '\n';
    }
    for (const ControlPoint& p : c.points) {
      out += "v ";
      append_vec3(out, identity ? p.p : finite_vec3(glm::dvec3(to_world * glm::vec4(p.p, 1.0f))));
      out += '\n';
    }
    out += "cstype bspline\ndeg 3\ncurv 3 ";
    append_int(out, n);
    for (std::size_t i = 0; i < n; ++i) {
      out += ' ';
      append_int(out, next_vertex + i);
    }
    out += "\nparm u";
    for (std::size_t k = 0; k < n + 4; ++k) {
      out += ' ';
      append_int(out, k);
    }
    out += "\nend\n";
    next_vertex += n;
  }
}

constexpr const char* kObjCurvesComment =
    "# Uniform cubic B-splines as OBJ free-form curves (knots 0, 1, 2, ...; the curve\n"
    "# spans parameters [3, n] for n control points). OBJ has no radius or normal:\n"
    "# they stay in the .fcurves file.\n";

}  // namespace

std::string format_obj(const Feather& f) {
  validate_feather(f);
  std::string out;
  out.reserve(512 + f.num_control_points() * 40);
  append_provenance_comment(out, f, "#");
  out += kObjCurvesComment;
  std::size_t next_vertex = 1;  // OBJ vertex indices are 1-based and global
  append_obj_curves(out, f, "", glm::mat4(1.0f), next_vertex);
  return out;
}

std::string format_obj(const ExportInstances& in) {
  validate_instances(in);
  std::string out = instances_comment(in, "#");
  out += kObjCurvesComment;
  out += "# OBJ has no instancing: every placement's curves are written carried into the scene,\n"
         "# named pK_FEATHER_... for placement K (from 0) of feather FEATHER.\n";
  std::size_t next_vertex = 1;
  for (std::size_t k = 0; k < in.placements.size(); ++k) {
    const ExportPlacement& p = in.placements[k];
    const ExportFeather& ef = in.feathers[p.feather];
    std::string prefix = "p";
    append_int(prefix, k);
    prefix += '_';
    prefix += ef.name;
    prefix += '_';
    append_obj_curves(out, *ef.feather, prefix, p.to_world, next_vertex);
  }
  return out;
}

// ---------------------------------------------------------------- Blender ---

// "(x, y, z)" as a Python tuple.
std::string py_tuple(std::initializer_list<float> v) {
  std::string r = "(";
  bool first = true;
  for (float x : v) {
    if (!first) r += ", ";
    first = false;
    append_float(r, finite_float(x));
  }
  return r + ")";
}

std::string py_number(float v) {
  std::string r;
  append_float(r, finite_float(v));
  return r;
}

// A Python string literal (repr-safe: printable, quotes and backslashes escaped).
std::string py_string(const std::string& s) {
  std::string r = "\"";
  for (char c : one_line(s)) {
    if (c == '"' || c == '\\') r += '\\';
    r += c;
  }
  return r + "\"";
}

namespace {

// The camera, image, LEDs, environment and card constants of a Blender script.
void append_blender_view(std::string& out, const ExportScene& s) {
  out += "\nCAMERA_EYE, CAMERA_TARGET, CAMERA_UP = " +
         py_tuple({s.camera.eye.x, s.camera.eye.y, s.camera.eye.z}) + ", " +
         py_tuple({s.camera.look_at.x, s.camera.look_at.y, s.camera.look_at.z}) + ", " +
         py_tuple({s.camera.up.x, s.camera.up.y, s.camera.up.z}) + "\nFOV_Y_DEG = ";
  append_float(out, s.camera.fov_deg);
  out += "\nWIDTH, HEIGHT, SPP, MAX_DEPTH = ";
  append_int(out, s.width);
  out += ", ";
  append_int(out, s.height);
  out += ", ";
  append_int(out, s.spp);
  out += ", ";
  append_int(out, s.max_depth);
  out += "\n# Dome LEDs: (centre, radius, radiance). A Cycles point light of radius r and power P\n"
         "# is a sphere of radiance P / (4 pi * pi r^2).\nLEDS = [\n";
  for (const ExportSphereLight& l : s.lights)
    out += "    (" + py_tuple({l.centre.x, l.centre.y, l.centre.z}) + ", " + py_number(l.radius) + ", " +
           py_tuple({l.radiance.x, l.radiance.y, l.radiance.z}) + "),\n";
  out += "]\nENVIRONMENT = ";
  out += s.environment ? py_tuple({s.environment->x, s.environment->y, s.environment->z}) : std::string("None");
  out += "\nCARD = ";  // (centre, half side, albedo) or None
  out += s.card ? "(" + py_tuple({s.card->centre.x, s.card->centre.y, s.card->centre.z}) + ", " +
                      py_number(s.card->half_side) + ", " +
                      py_tuple({s.card->albedo.x, s.card->albedo.y, s.card->albedo.z}) + ")"
                : std::string("None");
}

// The script's Python: helpers, the single feather's curves, a scene's feathers and
// placements, lights and camera, and the calls.
constexpr const char* kBlenderHelpers = R"PY(

def clear_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)


def surface_material(name, shader):
    """A material whose surface is one new shader node; returns both."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        nodes.remove(n)
    bsdf = nodes.new(shader)
    output = nodes.new("ShaderNodeOutputMaterial")
    mat.node_tree.links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    return mat, bsdf


)PY";
constexpr const char* kBlenderBuildCurves = R"PY(def curves_object(name, curves, sigma_a, beta_m, beta_n, eta, alpha_deg):
    """A Curves object of uniform cubic B-splines with the hair material, in the scene."""
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    cu = bpy.data.curves.new(name, "CURVE")
    cu.dimensions = "3D"
    for points in curves:
        sp = cu.splines.new("NURBS")
        sp.points.add(len(points) - 1)
        for p, (x, y, z, r) in zip(sp.points, points):
            p.co = (x, y, z, 1.0)
            p.radius = r
        sp.order_u = 4
        sp.use_endpoint_u = False
    ob = bpy.data.objects.new(name, cu)
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    bpy.ops.object.convert(target="CURVES")
    ob = bpy.context.view_layer.objects.active
    mat, hair = surface_material("plumage hair " + name, "ShaderNodeBsdfHairPrincipled")
    hair.parametrization = "ABSORPTION"
    hair.inputs["Absorption Coefficient"].default_value = sigma_a
    hair.inputs["Roughness"].default_value = beta_m
    hair.inputs["Radial Roughness"].default_value = beta_n
    hair.inputs["Coat"].default_value = 0.0
    hair.inputs["IOR"].default_value = eta
    hair.inputs["Offset"].default_value = math.radians(alpha_deg)
    hair.inputs["Random Roughness"].default_value = 0.0
    ob.data.materials.append(mat)
    return ob


)PY";
constexpr const char* kBlenderBuildOne = R"PY(def build_curves():
    return curves_object("feather", CURVES, SIGMA_A, BETA_M, BETA_N, ETA, ALPHA_DEG)


)PY";
constexpr const char* kBlenderLightsAndCamera = R"PY(def build_lights():
    for i, (centre, radius, radiance) in enumerate(LEDS):
        light = bpy.data.lights.new("LED %d" % (i + 1), "POINT")
        light.shadow_soft_size = radius
        peak = max(radiance)
        light.color = tuple(c / peak for c in radiance) if peak > 0 else (1.0, 1.0, 1.0)
        light.energy = peak * 4.0 * math.pi * math.pi * radius * radius
        ob = bpy.data.objects.new("LED %d" % (i + 1), light)
        ob.location = centre
        bpy.context.scene.collection.objects.link(ob)
    world = bpy.data.worlds.new("plumage world")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*(ENVIRONMENT or (0.0, 0.0, 0.0)), 1.0)
    background.inputs["Strength"].default_value = 1.0
    bpy.context.scene.world = world
    if CARD is not None:
        (cx, cy, cz), half, albedo = CARD
        mesh = bpy.data.meshes.new("card")
        mesh.from_pydata([(cx - half, cy - half, cz), (cx + half, cy - half, cz), (cx + half, cy + half, cz),
                          (cx - half, cy + half, cz)], [], [(0, 1, 2, 3)])
        mat, diffuse = surface_material("card", "ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = (*albedo, 1.0)
        diffuse.inputs["Roughness"].default_value = 0.0
        mesh.materials.append(mat)
        ob = bpy.data.objects.new("card", mesh)
        bpy.context.scene.collection.objects.link(ob)


def build_camera_and_settings():
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(FOV_Y_DEG)
    eye = Vector(CAMERA_EYE)
    cam.clip_start = 0.01
    cam.clip_end = 100.0 * max(1.0, (Vector(CAMERA_TARGET) - eye).length)
    ob = bpy.data.objects.new("camera", cam)
    ob.location = eye
    # Look along -Z with +Y toward CAMERA_UP.
    forward = (Vector(CAMERA_TARGET) - eye).normalized()
    right = forward.cross(Vector(CAMERA_UP)).normalized()
    up = right.cross(forward)
    from mathutils import Matrix
    ob.rotation_euler = Matrix((right, up, -forward)).transposed().to_euler()
    bpy.context.scene.collection.objects.link(ob)
    scene = bpy.context.scene
    scene.camera = ob
    scene.render.engine = "CYCLES"
    scene.render.resolution_x = WIDTH
    scene.render.resolution_y = HEIGHT
    scene.render.resolution_percentage = 100
    scene.cycles.samples = SPP
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.filter_width = 1.0  # a box over the pixel, as plumage
    scene.cycles.pixel_filter_type = "BOX"
    # Cycles counts bounces after the first hit: plumage's depth 1 (direct light) is 0 bounces.
    bounces = max(0, MAX_DEPTH - 1)
    for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                 "transparent_max_bounces"):
        setattr(scene.cycles, attr, bounces)
    scene.cycles.sample_clamp_direct = 0.0
    scene.cycles.sample_clamp_indirect = 0.0
    scene.cycles.blur_glossy = 0.0
    scene.cycles_curves.shape = "RIBBONS"
    scene.view_settings.view_transform = "Standard"


)PY";
constexpr const char* kBlenderMain = R"PY(clear_scene()
build_curves()
build_lights()
build_camera_and_settings()
print("plumage: built %d curves for %s" % (len(CURVES), NAME))
)PY";
constexpr const char* kBlenderBuildPlacements = R"PY(def build_placements():
    """Each distinct feather's Curves datablock once (the object that made it is not
    kept), then an object per placement that shares it, its matrix the placement's."""
    from mathutils import Matrix
    datas = []
    for feather in FEATHERS:
        ob = curves_object(*feather)
        data = ob.data
        data.use_fake_user = True
        bpy.data.objects.remove(ob)
        datas.append(data)
    for k, (i, rows) in enumerate(PLACEMENTS):
        ob = bpy.data.objects.new("p%d_%s" % (k, FEATHERS[i][0]), datas[i])
        ob.matrix_world = Matrix(rows)
        bpy.context.scene.collection.objects.link(ob)


)PY";
constexpr const char* kBlenderSceneMain = R"PY(clear_scene()
build_placements()
build_lights()
build_camera_and_settings()
print("plumage: built %d feathers in %d placements" % (len(FEATHERS), len(PLACEMENTS)))
)PY";

}  // namespace

std::string format_blender(const Feather& f, const ExportScene& s) {
  validate_feather(f);
  std::string out;
  out.reserve(8192 + f.num_control_points() * 48);
  out += "# Blender 3.4+ script written by `plumage export`: run `blender -b -P THIS.py -o //render_ -F OPEN_EXR -f 1`\n"
         "# to render, or `blender -P THIS.py` to open the scene. Units: 1 Blender unit = 1 mm.\n";
  append_provenance_comment(out, f, "#");
  append_scene_comment(out, s, "#");
  out += "# Curves: uniform cubic B-splines (NURBS order 4, uniform knots) with the radius plumage draws\n"
         "# them with, converted to a Curves object so that Cycles renders them as hair (ray-facing\n"
         "# ribbons, as plumage's hair mode draws barbs). docs/exporters.md says what is approximated.\n"
         "import math\n\nimport bpy\nfrom mathutils import Vector\n\n";
  out += "# One tuple of (x, y, z, radius) control points per curve; the shaft first.\nCURVES = [\n";
  for (const Curve& c : f.curves) {
    out += "    (";
    const std::vector<float> radii = render_radii(f, c);
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      const ControlPoint& p = c.points[i];
      out += py_tuple({p.p.x, p.p.y, p.p.z, radii[i]});
      out += ", ";
    }
    out += "),\n";
  }
  out += "]\n";
  out += "SIGMA_A = " + py_tuple({s.material.sigma_a.x, s.material.sigma_a.y, s.material.sigma_a.z}) +
         "  # per unit fibre radius, as Cycles' absorption coefficient\n";
  out += "BETA_M, BETA_N, ETA = " + py_number(s.material.beta_m) + ", " + py_number(s.material.beta_n) + ", " +
         py_number(s.material.eta);
  out += "\n# Cycles' Offset follows pbrt's alpha (minus plumage's), in radians.\nALPHA_DEG = ";
  append_float(out, -s.material.alpha_deg);
  append_blender_view(out, s);
  out += "\nNAME = " + py_string(f.provenance.source.empty() ? "plumage feather" : f.provenance.source) + "\n";
  out += kBlenderHelpers;
  out += kBlenderBuildCurves;
  out += kBlenderBuildOne;
  out += kBlenderLightsAndCamera;
  out += kBlenderMain;
  return out;
}

std::string format_blender(const ExportInstances& in, const ExportScene& s) {
  validate_instances(in);
  std::string out;
  out += "# Blender 3.4+ script written by `plumage export`: run `blender -b -P THIS.py -o //render_ -F OPEN_EXR -f 1`\n"
         "# to render, or `blender -P THIS.py` to open the scene. Units: 1 Blender unit = 1 mm.\n";
  out += instances_comment(in, "#");
  append_scene_comment(out, s, "#");
  out += "# Each distinct feather is one Curves datablock (uniform cubic B-splines as NURBS order 4, with\n"
         "# the radius plumage draws them with) and its own Principled Hair material; each placement is an\n"
         "# object that shares it, its matrix the placement's. docs/exporters.md says what is approximated.\n"
         "import math\n\nimport bpy\nfrom mathutils import Vector\n\n";
  out += "# Per feather: (name, curves of (x, y, z, radius) control points, sigma_a per unit radius,\n"
         "# beta_m, beta_n, eta, Cycles' Offset in degrees: minus plumage's alpha).\nFEATHERS = [\n";
  for (const ExportFeather& ef : in.feathers) {
    out += "    (" + py_string(ef.name) + ", (\n";
    for (const Curve& c : ef.feather->curves) {
      out += "        (";
      const std::vector<float> radii = render_radii(*ef.feather, c);
      for (std::size_t i = 0; i < c.points.size(); ++i) {
        out += py_tuple({c.points[i].p.x, c.points[i].p.y, c.points[i].p.z, radii[i]});
        out += ", ";
      }
      out += "),\n";
    }
    const ExportMaterial& m = ef.material;
    out += "    ), " + py_tuple({m.sigma_a.x, m.sigma_a.y, m.sigma_a.z}) + ", " + py_number(m.beta_m) + ", " +
           py_number(m.beta_n) + ", " + py_number(m.eta) + ", " + py_number(-m.alpha_deg) + "),\n";
  }
  out += "]\n# Per placement: (feather index, its 4x4 matrix row by row).\nPLACEMENTS = [\n";
  for (const ExportPlacement& p : in.placements) {
    out += "    (";
    append_int(out, p.feather);
    out += ", (";
    for (int row = 0; row < 4; ++row) {
      const glm::vec4 r(p.to_world[0][row], p.to_world[1][row], p.to_world[2][row], p.to_world[3][row]);
      out += py_tuple({finite_float(r.x), finite_float(r.y), finite_float(r.z), finite_float(r.w)});
      out += row < 3 ? ", " : "";
    }
    out += ")),\n";
  }
  out += "]";
  append_blender_view(out, s);
  out += "\n";
  out += kBlenderHelpers;
  out += kBlenderBuildCurves;
  out += kBlenderBuildPlacements;
  out += kBlenderLightsAndCamera;
  out += kBlenderSceneMain;
  return out;
}

std::string export_text(const Feather& f, ExportFormat format, const ExportScene& s) {
  switch (format) {
    case ExportFormat::Fcurves:
      return format_fcurves(f);
    case ExportFormat::Pbrt:
      return format_pbrt_v4(f, s);
    case ExportFormat::PbrtV3:
      return format_pbrt_v3(f, s);
    case ExportFormat::Mitsuba:
      return format_mitsuba_curves(f);
    case ExportFormat::Obj:
      return format_obj(f);
    case ExportFormat::Blender:
      return format_blender(f, s);
  }
  throw Error("unknown export format");
}

std::filesystem::path mitsuba_scene_path(const std::filesystem::path& curves) {
  std::filesystem::path scene = curves;
  scene.replace_extension(curves.extension() == ".xml" ? ".scene.xml" : ".xml");
  return scene;
}

void export_feather(const std::filesystem::path& path, const Feather& f, ExportFormat format,
                    const ExportScene& s) {
  // Build the whole text first: a failure leaves nothing on disk.
  const std::string text = export_text(f, format, s);
  if (format != ExportFormat::Mitsuba) {
    write_file_atomic(path, text);
    return;
  }
  const std::string scene = format_mitsuba_scene(f, s, path.filename().string());
  write_file_atomic(path, text);
  write_file_atomic(mitsuba_scene_path(path), scene);
}

std::filesystem::path mitsuba_feather_path(const std::filesystem::path& path, const std::string& name) {
  std::filesystem::path p = path;
  p.replace_filename(path.stem().string() + "." + name + ".txt");
  return p;
}

void export_instances(const std::filesystem::path& path, const ExportInstances& in, ExportFormat format,
                      const ExportScene& s) {
  if (format == ExportFormat::Fcurves)
    throw Error("a scene's feathers are .fcurves files already; export one of them, or give another --format");
  // Every text first: a failure leaves nothing on disk.
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  switch (format) {
    case ExportFormat::Pbrt:
      files.emplace_back(path, format_pbrt_v4(in, s));
      break;
    case ExportFormat::PbrtV3:
      files.emplace_back(path, format_pbrt_v3(in, s));
      break;
    case ExportFormat::Obj:
      files.emplace_back(path, format_obj(in));
      break;
    case ExportFormat::Blender:
      files.emplace_back(path, format_blender(in, s));
      break;
    case ExportFormat::Mitsuba: {
      std::vector<std::string> names;
      for (const ExportFeather& ef : in.feathers) {
        const std::filesystem::path curves = mitsuba_feather_path(path, ef.name);
        names.push_back(curves.filename().string());
        files.emplace_back(curves, format_mitsuba_curves(*ef.feather));
      }
      files.emplace_back(mitsuba_scene_path(path), format_mitsuba_scene(in, s, names));
      break;
    }
    case ExportFormat::Fcurves:
      break;
  }
  for (const auto& [file, text] : files) write_file_atomic(file, text);
}

}  // namespace plumage
