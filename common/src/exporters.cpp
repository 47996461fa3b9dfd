// Exporters to pbrt-v4, pbrt-v3, Mitsuba 3 and Wavefront OBJ (exporters.h).
//
// All four take uniform cubic B-spline control points as they are (pbrt's and
// Mitsuba's "bspline" curves and OBJ's `cstype bspline` with uniform knots are the
// same curve as ours). What they cannot hold is said in a comment in the output.
#include "plumage/common/exporters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include "float_text.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"

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
                                   {ExportFormat::Obj, "obj", ".obj"}};

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
  append_int(out, f.num_control_points());
  out += " control points; units mm\n";
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

// Camera placement looking at the dorsal side (+Z) so the whole feather fills the frame.
struct Framing {
  glm::vec3 eye, target;
  float fov_deg;
};

Framing frame_feather(const Feather& f) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Curve& c : f.curves)
    for (const ControlPoint& p : c.points) {
      const glm::dvec3 q(p.p), r(p.radius);
      lo = glm::min(lo, q - r);
      hi = glm::max(hi, q + r);
    }
  if (!(lo.x <= hi.x)) lo = glm::dvec3(-1), hi = glm::dvec3(1);  // nothing to frame
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double half = std::max({0.5 * (hi.x - lo.x), 0.5 * (hi.y - lo.y), 1e-3});
  const double fov = 30.0;
  const double distance = 1.1 * half / std::tan(0.5 * fov * std::numbers::pi / 180.0) + 0.5 * (hi.z - lo.z);
  return {finite_vec3(centre + glm::dvec3(0, 0, distance)), finite_vec3(centre), float(fov)};
}

enum class PbrtVersion { V3, V4 };

void append_pbrt_curve(std::string& out, const Curve& c, PbrtVersion v) {
  const auto& cp = c.points;
  const std::size_t n = cp.size();
  const std::size_t segments = n - 3;
  const bool ribbon = c.kind == CurveKind::Barb;
  out += "Shape \"curve\" \"string basis\" [ \"bspline\" ] \"string type\" [ \"";
  out += ribbon ? "ribbon" : "cylinder";
  out += v == PbrtVersion::V4 ? "\" ]\n  \"point3 P\" [" : "\" ]\n  \"point P\" [";
  for (const ControlPoint& p : cp) {
    out += ' ';
    append_vec3(out, p.p);
  }
  // pbrt interpolates width linearly from the curve's start to its end; our
  // radius is a B-spline per control point, so its end values are used.
  out += " ]\n  \"float width0\" [ ";
  append_float(out, finite_float(2 * at_joint(cp, 0, &ControlPoint::radius)));
  out += " ] \"float width1\" [ ";
  append_float(out, finite_float(2 * at_joint(cp, segments, &ControlPoint::radius)));
  out += " ]";
  if (ribbon) {
    // Ribbons need the normal at each segment joint: segments + 1 of them.
    out += "\n  \"normal N\" [";
    for (std::size_t k = 0; k <= segments; ++k) {
      // Never zero: the middle weight 4/6 outweighs the other two (1/6 each) for unit normals.
      const glm::dvec3 nn = at_joint(cp, k, &ControlPoint::n);
      const glm::vec3 unit(nn / glm::length(nn));
      out += ' ';
      append_vec3(out, unit);
    }
    out += " ]";
  }
  out += '\n';
}

std::string format_pbrt(const Feather& f, const ExportOptions& o, PbrtVersion v) {
  validate_feather(f);
  const bool v4 = v == PbrtVersion::V4;
  std::string out;
  out.reserve(1024 + f.num_control_points() * 48);
  out += v4 ? "# pbrt-v4 scene" : "# pbrt-v3 scene";
  out += " written by `plumage export`. Curves are uniform cubic B-splines in mm.\n";
  append_provenance_comment(out, f, "#");
  if (!f.albedo.texture.empty())
    out += "# The albedo texture \"" + one_line(f.albedo.texture) +
           "\" is not exported: the hair material uses the constant albedo colour.\n";
  const Framing fr = frame_feather(f);
  out += "# Mirror x so the image shows the dorsal side as seen from +Z (pbrt's LookAt is left-handed).\n";
  out += "Scale -1 1 1\nLookAt ";
  append_vec3(out, fr.eye);
  out += "  ";
  append_vec3(out, fr.target);
  out += "  0 1 0\nCamera \"perspective\" \"float fov\" [ ";
  append_float(out, fr.fov_deg);
  out += " ]\n";
  out += v4 ? "Sampler \"zsobol\" \"integer pixelsamples\" [ 64 ]\n"
              "Integrator \"volpath\" \"integer maxdepth\" [ 32 ]\n"
              "Film \"rgb\" \"string filename\" [ \""
            : "Sampler \"halton\" \"integer pixelsamples\" [ 64 ]\n"
              "Integrator \"path\" \"integer maxdepth\" [ 32 ]\n"
              "Film \"image\" \"string filename\" [ \"";
  out += one_line(o.image_filename);
  out += "\" ]\n  \"integer xresolution\" [ ";
  append_int(out, o.image_width);
  out += " ] \"integer yresolution\" [ ";
  append_int(out, o.image_height);
  out += " ]\n\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n\nAttributeBegin\n";
  // Hair BCSDF (Chiang et al. 2016) with absorption derived from the albedo.
  out += v4 ? "Material \"hair\" \"rgb reflectance\" [ " : "Material \"hair\" \"rgb color\" [ ";
  append_vec3(out, f.albedo.color);
  out += " ]\n";
  for (const Curve& c : f.curves) append_pbrt_curve(out, c, v);
  out += "AttributeEnd\n";
  if (!v4) out += "WorldEnd\n";
  return out;
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

std::string format_pbrt_v4(const Feather& f, const ExportOptions& o) {
  return format_pbrt(f, o, PbrtVersion::V4);
}
std::string format_pbrt_v3(const Feather& f, const ExportOptions& o) {
  return format_pbrt(f, o, PbrtVersion::V3);
}

std::string format_mitsuba_curves(const Feather& f) {
  validate_feather(f);
  // Mitsuba's loader takes no comments: numbers only, a blank line ends a curve.
  std::string out;
  out.reserve(f.num_control_points() * 40);
  bool first = true;
  for (const Curve& c : f.curves) {
    if (!first) out += '\n';
    first = false;
    for (const ControlPoint& p : c.points) {
      append_vec3(out, p.p);
      out += ' ';
      append_float(out, p.radius);
      out += '\n';
    }
  }
  return out;
}

std::string format_obj(const Feather& f) {
  validate_feather(f);
  std::string out;
  out.reserve(512 + f.num_control_points() * 40);
  append_provenance_comment(out, f, "#");
  out +=
      "# Uniform cubic B-splines as OBJ free-form curves (knots 0, 1, 2, ...; the curve\n"
      "# spans parameters [3, n] for n control points). OBJ has no radius or normal:\n"
      "# they stay in the .fcurves file.\n";
  std::size_t next_vertex = 1;  // OBJ vertex indices are 1-based and global
  std::size_t barb = 0;
  for (const Curve& c : f.curves) {
    const std::size_t n = c.points.size();
    if (c.kind == CurveKind::Shaft) {
      out += "o shaft\n";
    } else {
      out += "o barb_";
      out += to_string(c.side);
      out += '_';
      append_int(out, barb++);
      out += '\n';
    }
    for (const ControlPoint& p : c.points) {
      out += "v ";
      append_vec3(out, p.p);
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
  return out;
}

std::string export_text(const Feather& f, ExportFormat format, const ExportOptions& o) {
  switch (format) {
    case ExportFormat::Fcurves:
      return format_fcurves(f);
    case ExportFormat::Pbrt:
      return format_pbrt_v4(f, o);
    case ExportFormat::PbrtV3:
      return format_pbrt_v3(f, o);
    case ExportFormat::Mitsuba:
      return format_mitsuba_curves(f);
    case ExportFormat::Obj:
      return format_obj(f);
  }
  throw Error("unknown export format");
}

void export_feather(const std::filesystem::path& path, const Feather& f, ExportFormat format,
                    const ExportOptions& o) {
  // Build the whole text first: a failure leaves nothing on disk.
  write_file_atomic(path, export_text(f, format, o));
}

}  // namespace plumage
