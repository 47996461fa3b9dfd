// The .fcurves reader and writer (docs/curve-format.md): malformed files each
// get their exact place and message, random feathers round-trip bit for bit,
// and no prefix or mutation of a file crashes the reader or makes it allocate
// what a lying count asks for.
#include "plumage/common/curve_format.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>
#include <vector>

#include "feather_samples.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"

using namespace plumage;

namespace {

// Line numbers below refer to this file (1-based).
const std::vector<std::string> kBase = {
    "fcurves 1",                 // 1
    "units mm",                  // 2
    "source \"preset:test\"",    // 3
    "seed 7",                    // 4
    "albedo color 0.5 0.4 0.3",  // 5
    "substructure left barbules 20 ramus_radius 0.02 barbule_radius 0.005 elevation 40 azimuth 10 "
    "hooked_fraction 0.2 ribbon_width 0.3",  // 6
    "substructure right barbules 21 ramus_radius 0.02 barbule_radius 0.005 elevation 40 azimuth -10 "
    "hooked_fraction 0.2 ribbon_width 0.3",  // 7
    "curves 2",                              // 8
    "curve shaft none bspline 4 root 0",     // 9
    "0 0 0 0.5 0 0 1",                       // 10
    "0 1 0 0.5 0 0 1",                       // 11
    "0 2 0 0.4 0 0 1",                       // 12
    "0 3 0 0.3 0 0 1",                       // 13
    "curve barb left bspline 4 root 0.5",    // 14
    "0 1.5 0 0.1 0 0 1",                     // 15
    "-1 2 0 0.1 0 0 1",                      // 16
    "-2 2.5 0 0.1 0 0 1",                    // 17
    "-3 3 0 0.1 0 0 1",                      // 18
    "end",                                   // 19
};

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}
std::string with_line(int n, const std::string& text) {
  auto l = kBase;
  l[n - 1] = text;
  return join(l);
}
std::string without_line(int n) {
  auto l = kBase;
  l.erase(l.begin() + (n - 1));
  return join(l);
}
std::string insert_before(int n, const std::string& text) {
  auto l = kBase;
  l.insert(l.begin() + (n - 1), text);
  return join(l);
}
// Column (1-based) of the `occurrence`-th `needle` in `line`.
int col(const std::string& line, const std::string& needle, int occurrence = 1) {
  std::size_t at = std::string::npos, from = 0;
  for (int i = 0; i < occurrence; ++i) {
    at = line.find(needle, from);
    from = at + 1;
  }
  EXPECT_NE(at, std::string::npos) << needle << " not in " << line;
  return int(at) + 1;
}
int end_col(const std::string& line) { return int(line.size()) + 1; }

struct Malformed {
  std::string name;
  std::string text;
  int line, column;
  std::string fragment;  // must occur in the message
};

std::vector<Malformed> malformed_files() {
  const std::string sub_left = kBase[5];
  auto replace = [](std::string s, const std::string& from, const std::string& to) {
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  const std::string no_hooked = replace(sub_left, "hooked_fraction 0.2 ", "");
  const std::string no_width_value = replace(sub_left, " 0.3", "");
  const std::string typo_key = replace(sub_left, "azimuth", "azimut");
  std::vector<Malformed> t = {
      {"empty file", "", 1, 1, "missing header: the first line must be 'fcurves 1'"},
      {"not a curve file", "ply\nformat ascii 1.0\n", 1, 1, "missing header"},
      {"byte-order mark", "\xEF\xBB\xBF" + join(kBase), 1, 1, "UTF-8 byte-order mark"},
      {"comment before header", "# hi\n" + join(kBase), 1, 1, "missing header"},
      {"version from the future", with_line(1, "fcurves 2"), 1, 9,
       "format version 2 is newer than this reader (1): upgrade Plumage to read it"},
      {"version zero", with_line(1, "fcurves 0"), 1, 9, "format version must be 1 or more"},
      {"version missing", with_line(1, "fcurves"), 1, 8, "expected a version number after 'fcurves'"},
      {"version not a number", with_line(1, "fcurves one"), 1, 9,
       "expected a whole number >= 0, found 'one'"},
      {"junk after header", with_line(1, "fcurves 1 extra"), 1, 11, "unexpected 'extra'"},
      {"second header", insert_before(3, "fcurves 1"), 3, 1, "second 'fcurves' header"},
      {"unknown record", insert_before(5, "colour 1 2 3"), 5, 1, "unknown record 'colour'"},
      {"units not mm", with_line(2, "units cm"), 2, 7, "units: only 'mm' is supported"},
      {"units twice", insert_before(3, "units mm"), 3, 1, "second 'units' record (first on line 2)"},
      {"negative seed", with_line(4, "seed -1"), 4, 6, "seed: expected a whole number >= 0, found '-1'"},
      {"seed too large", with_line(4, "seed 99999999999999999999999"), 4, 6,
       "seed: '99999999999999999999999' is too large"},
      {"source unquoted", with_line(3, "source preset"), 3, 8, "source: expected a string in double quotes"},
      {"unterminated string", with_line(3, "source \"abc"), 3, 8, "unterminated string"},
      {"unknown escape", with_line(3, "source \"a\\qb\""), 3, 10, "unknown escape in string"},
      {"text glued to string", with_line(3, "source \"a\"b"), 3, 11,
       "expected a space after the closing '\"'"},
      {"stray quote in word", with_line(4, "seed 4\"2"), 4, 7, "stray '\"' inside a word"},
      {"control character", with_line(4, "seed 4\x01"), 4, 7, "control character"},
      {"control character in string", with_line(3, "source \"a\tb\""), 3, 10, "control character"},
      {"string as record name", insert_before(5, "\"albedo\" color 1 1 1"), 5, 1,
       "expected a record name, found a string"},
      {"albedo kind unknown", with_line(5, "albedo colour 1 1 1"), 5, 8,
       "albedo: expected 'color', 'texture', 'shaft' or 'scale', found 'colour'"},
      {"albedo negative", with_line(5, "albedo color 0.5 -0.1 0.3"), 5, 18,
       "albedo colour: must not be negative, found '-0.1'"},
      {"albedo too few numbers", with_line(5, "albedo color 0.5 0.4"), 5, 21,
       "'albedo' record is incomplete: expected 'albedo color R G B'"},
      {"albedo colour twice", insert_before(6, "albedo color 1 1 1"), 6, 1,
       "second 'albedo color' record (first on line 5)"},
      {"shaft colour with a partial triple", insert_before(6, "albedo shaft 1 1 1 0.5 0.5"), 6, 27,
       "'albedo shaft' record is incomplete: expected whole R G B triples (5 numbers given)"},
      {"shaft colour too short", insert_before(6, "albedo shaft 1 1"), 6, 17,
       "'albedo' record is incomplete: expected 'albedo shaft R G B [R G B ...]'"},
      {"shaft colour negative at a station", insert_before(6, "albedo shaft 1 1 1 0.5 -0.5 0.5"), 6, 24,
       "albedo shaft colour: must not be negative, found '-0.5'"},
      {"texture rectangle inverted", insert_before(6, "albedo texture \"a.png\" 0 0 -1 1"), 6, 28,
       "albedo texture: XMAX must be greater than XMIN"},
      {"texture name empty", insert_before(6, "albedo texture \"\" 0 0 1 1"), 6, 16,
       "albedo texture: the file name is empty"},
      {"substructure side unknown", with_line(6, replace(sub_left, "left", "middle")), 6, 14,
       "substructure: expected 'left' or 'right', found 'middle'"},
      {"substructure key unknown", with_line(6, typo_key), 6, col(typo_key, "azimut"),
       "substructure: unknown key 'azimut'"},
      {"substructure key missing", with_line(6, no_hooked), 6, end_col(no_hooked),
       "substructure left: missing required key 'hooked_fraction'"},
      {"substructure key twice", with_line(6, sub_left + " barbules 3"), 6,
       col(sub_left + " barbules 3", "barbules", 2), "substructure: key 'barbules' given twice"},
      {"substructure value missing", with_line(6, no_width_value), 6, end_col(no_width_value),
       "substructure: expected a value after 'ribbon_width'"},
      {"elevation zero", with_line(6, replace(sub_left, "elevation 40", "elevation 0")), 6,
       col(sub_left, "40"), "substructure left elevation: value 0 is outside [1, 90] degrees"},
      {"hooked fraction above one",
       with_line(6, replace(sub_left, "hooked_fraction 0.2", "hooked_fraction 1.5")), 6,
       col(sub_left, "0.2 ribbon"), "substructure left hooked_fraction: value 1.5 is outside [0, 1]"},
      {"azimuth 90 (refused at render before)", with_line(6, replace(sub_left, "azimuth 10", "azimuth 90")), 6,
       col(sub_left, "10 hooked"), "substructure left azimuth: value 90 is outside (-90, 90) degrees"},
      {"barbules fractional", with_line(6, replace(sub_left, "barbules 20", "barbules 2.5")), 6,
       col(sub_left, "20"), "barbules: expected a whole number >= 0, found '2.5'"},
      {"substructure twice", insert_before(7, sub_left), 7, 1,
       "second 'substructure left' record (first on line 6)"},
      {"curve count too high", with_line(8, "curves 3"), 19, 1,
       "the file has 2 curves but the 'curves' record on line 8 declares 3"},
      {"curve count absurd", with_line(8, "curves 18446744073709551615"), 19, 1, "the file has 2 curves"},
      {"curve count too low", with_line(8, "curves 1"), 14, 1,
       "more curves than the 'curves 1' record on line 8 declares"},
      {"curves record missing", without_line(8), 8, 1, "missing 'curves N' record before the first curve"},
      {"units record missing", without_line(2), 8, 1, "missing 'units mm' record before the first curve"},
      {"header record after curves", insert_before(14, "seed 9"), 14, 1,
       "header record 'seed' after the first curve: move it above the curves"},
      {"point with 6 numbers", with_line(11, "0 1 0 0.5 0 0"), 11, 14,
       "control point: expected 7 numbers (x y z radius nx ny nz), found 6"},
      {"point with 8 numbers", with_line(11, "0 1 0 0.5 0 0 1 9"), 11, 17, "expected 7 numbers"},
      {"NaN coordinate", with_line(11, "nan 1 0 0.5 0 0 1"), 11, 1, "x: must be finite, found 'nan'"},
      {"infinite radius", with_line(11, "0 1 0 inf 0 0 1"), 11, 7, "radius: must be finite, found 'inf'"},
      {"float out of range", with_line(11, "0 1e39 0 0.5 0 0 1"), 11, 3,
       "y: '1e39' is out of range for a 32-bit float"},
      {"not a number", with_line(11, "0 1 0x10 0.5 0 0 1"), 11, 5, "z: expected a number, found '0x10'"},
      {"plus sign", with_line(11, "0 +1 0 0.5 0 0 1"), 11, 3, "y: expected a number, found '+1'"},
      {"negative radius", with_line(11, "0 1 0 -0.5 0 0 1"), 11, 7,
       "radius: must not be negative, found '-0.5'"},
      {"zero normal", with_line(11, "0 1 0 0.5 0 0 0"), 11, 11, "normal: zero length"},
      {"too few points", with_line(9, "curve shaft none bspline 3 root 0"), 9, 26,
       "a cubic B-spline needs at least 4 control points, found 3"},
      {"npoints too high", with_line(9, "curve shaft none bspline 5 root 0"), 14, 1,
       "expected point 5 of 5 of the curve on line 9, found 'curve'"},
      {"extra point line", insert_before(14, "0 4 0 0.3 0 0 1"), 14, 1,
       "the curve on line 9 has more point lines than its NPOINTS says"},
      {"numbers outside a curve", insert_before(5, "1 2 3"), 5, 1, "unexpected numbers outside a curve"},
      {"npoints absurd", with_line(14, "curve barb left bspline 1000000000000 root 0.5"), 19, 1,
       "expected point 5 of 1000000000000 of the curve on line 14, found 'end'"},
      {"root above one", with_line(14, "curve barb left bspline 4 root 1.5"), 14, 32,
       "root: must be in [0, 1] (a fraction of the shaft length), found '1.5'"},
      {"root keyword misspelt", with_line(14, "curve barb left bspline 4 rot 0.5"), 14, 27,
       "expected 'root', found 'rot'"},
      {"shaft with a side", with_line(9, "curve shaft left bspline 4 root 0"), 9, 13,
       "the shaft belongs to no vane: its side must be 'none'"},
      {"barb without a side", with_line(14, "curve barb none bspline 4 root 0.5"), 14, 12,
       "a barb belongs to a vane: its side must be 'left' or 'right'"},
      {"two shafts", with_line(14, "curve shaft none bspline 4 root 0.5"), 14, 7,
       "second shaft (the first is on line 9)"},
      {"unknown kind", with_line(14, "curve quill left bspline 4 root 0.5"), 14, 7,
       "curve kind: expected 'shaft', 'barb' or 'down', found 'quill'"},
      {"down barb without a side", with_line(14, "curve down none bspline 4 root 0.5"), 14, 12,
       "a down barb belongs to a vane: its side must be 'left' or 'right'"},
      {"unknown side", with_line(14, "curve barb up bspline 4 root 0.5"), 14, 12,
       "vane side: expected 'none', 'left' or 'right', found 'up'"},
      {"unknown basis", with_line(14, "curve barb left bezier 4 root 0.5"), 14, 17,
       "basis: only 'bspline' (uniform cubic B-spline) is supported, found 'bezier'"},
      {"curve record short", with_line(14, "curve barb left bspline 4"), 14, 26,
       "'curve' record is incomplete"},
      {"truncated inside a curve", join({kBase.begin(), kBase.begin() + 16}), 16, 17,
       "file ends inside the curve on line 14: expected point 3 of 4 (truncated file?)"},
      {"missing end", without_line(19), 18, 17, "missing 'end' at the end of the file"},
      {"junk after end", with_line(19, "end now"), 19, 5, "unexpected 'now' after 'end'"},
      {"text after end", join(kBase) + "\n# fine\ncurve barb left bspline 4 root 0\n", 22, 1,
       "text after 'end': a file holds one feather"},
  };
  // Shaft after a barb: move the shaft's five lines after the barb's.
  std::vector<std::string> swapped(kBase.begin(), kBase.begin() + 8);
  swapped.insert(swapped.end(), kBase.begin() + 13, kBase.begin() + 18);
  swapped.insert(swapped.end(), kBase.begin() + 8, kBase.begin() + 13);
  swapped.push_back("end");
  t.push_back({"shaft after a barb", join(swapped), 14, 7, "the shaft must be the first curve"});
  return t;
}

// Bitwise equality of every float, which operator== cannot see for -0.0.
void expect_bit_identical(const Feather& a, const Feather& b) {
  ASSERT_EQ(a.curves.size(), b.curves.size());
  for (std::size_t i = 0; i < a.curves.size(); ++i) {
    const auto &pa = a.curves[i].points, &pb = b.curves[i].points;
    ASSERT_EQ(pa.size(), pb.size());
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a.curves[i].root), std::bit_cast<std::uint32_t>(b.curves[i].root));
    for (std::size_t k = 0; k < pa.size(); ++k) {
      for (const auto& [x, y] : {std::pair{pa[k].p, pb[k].p}, std::pair{pa[k].n, pb[k].n}})
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(std::bit_cast<std::uint32_t>(x[c]), std::bit_cast<std::uint32_t>(y[c])) << "curve " << i;
      ASSERT_EQ(std::bit_cast<std::uint32_t>(pa[k].radius), std::bit_cast<std::uint32_t>(pb[k].radius));
    }
  }
}

// What parse_fcurves says of `text` read as `name`: its error message, or
// "accepted".
std::string parse_error(const std::string& text, const std::string& name) {
  try {
    parse_fcurves(text, name);
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(CurveFormat, BaseFileParses) {
  const Feather f = parse_fcurves(join(kBase), "base.fcurves");
  ASSERT_EQ(f.curves.size(), 2u);
  EXPECT_EQ(f.curves[0].kind, CurveKind::Shaft);
  EXPECT_EQ(f.curves[1].side, VaneSide::Left);
  EXPECT_EQ(f.curves[1].root, 0.5f);
  EXPECT_EQ(f.curves[1].points[2].p, glm::vec3(-2, 2.5f, 0));
  EXPECT_EQ(f.provenance.source, "preset:test");
  EXPECT_EQ(f.provenance.seed, 7u);
  EXPECT_EQ(f.left.barbules_per_side, 20);
  EXPECT_EQ(f.right.barbules_per_side, 21);
  EXPECT_EQ(f.right.azimuth_deg, -10.0f);
  EXPECT_EQ(f.left.hooked_fraction, 0.2f);
  EXPECT_EQ(f.albedo.color, glm::vec3(0.5f, 0.4f, 0.3f));
  EXPECT_TRUE(f.albedo.texture.empty());
}

TEST(CurveFormat, MalformedFilesGetPlaceAndMessage) {
  const auto table = malformed_files();
  ASSERT_GE(table.size(), 30u);
  for (const Malformed& m : table) {
    SCOPED_TRACE(m.name);
    try {
      parse_fcurves(m.text, "bad.fcurves");
      ADD_FAILURE() << "parsed without error: " << m.name;
    } catch (const Error& e) {
      EXPECT_EQ(e.where().file, "bad.fcurves");
      EXPECT_EQ(e.where().line, m.line) << e.what();
      EXPECT_EQ(e.where().column, m.column) << e.what();
      EXPECT_NE(e.message().find(m.fragment), std::string::npos) << "message: " << e.message();
    }
  }
}

TEST(CurveFormat, ExactMessages) {
  auto message = [](const std::string& text) {
    try {
      parse_fcurves(text, "f.fcurves");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message(with_line(1, "fcurves 2")),
            "f.fcurves:1:9: format version 2 is newer than this reader (1): upgrade Plumage to read it");
  EXPECT_EQ(message(with_line(11, "0 1 0 -0.5 0 0 1")),
            "f.fcurves:11:7: radius: must not be negative, found '-0.5'");
  EXPECT_EQ(message(without_line(19)),
            "f.fcurves:18:17: missing 'end' at the end of the file (truncated file?)");
}

TEST(CurveFormat, CommentsBlankLinesTabsAndCrlf) {
  std::string text;
  for (const auto& l : kBase) text += "\t" + l + "   # comment \"with quotes\r\n\r\n";
  text.erase(0, 1);  // the header must start the first line
  EXPECT_EQ(parse_fcurves(text), parse_fcurves(join(kBase)));
  // '#' inside a quoted string is text, not a comment.
  EXPECT_EQ(parse_fcurves(with_line(3, "source \"a # b\" # c")).provenance.source, "a # b");
  EXPECT_EQ(parse_fcurves(with_line(3, "source \"q\\\"\\\\\"")).provenance.source, "q\"\\");
}

TEST(CurveFormat, NormalsWithinToleranceKeptOthersRenormalised) {
  // |n| = 1.0005: inside the 1e-3 tolerance, kept as written.
  Feather near = parse_fcurves(with_line(11, "0 1 0 0.5 0 0 1.0005"));
  EXPECT_EQ(near.curves[0].points[1].n, glm::vec3(0, 0, 1.0005f));
  // |n| = 1.005 and 2: renormalised.
  EXPECT_EQ(parse_fcurves(with_line(11, "0 1 0 0.5 0 0 1.005")).curves[0].points[1].n, glm::vec3(0, 0, 1));
  Feather far = parse_fcurves(with_line(11, "0 1 0 0.5 0 0 2"));
  EXPECT_EQ(far.curves[0].points[1].n, glm::vec3(0, 0, 1));
  Feather diag = parse_fcurves(with_line(11, "0 1 0 0.5 0.7 0 0.7"));
  EXPECT_NEAR(glm::length(diag.curves[0].points[1].n), 1.0f, 1e-6f);
  // Tiny but non-zero normals are rejected with the zero-length message too.
  EXPECT_THROW(parse_fcurves(with_line(11, "0 1 0 0.5 1e-30 0 0")), Error);
}

TEST(CurveFormat, RandomFeathersRoundTripExactly) {
  std::mt19937_64 rng(20210611);
  for (int i = 0; i < 300; ++i) {
    SCOPED_TRACE("feather " + std::to_string(i));
    const Feather f = samples::random_feather(rng);
    const std::string text = format_fcurves(f);
    const Feather g = parse_fcurves(text, "random.fcurves");
    ASSERT_EQ(g, f);
    expect_bit_identical(f, g);
    ASSERT_EQ(format_fcurves(g), text);
  }
}

TEST(CurveFormat, MedullaRecordReadsWritesAndIsChecked) {
  // The fibres' medulla: read, written back only when there is one, refused outside
  // its ranges with the place and the setting named.
  const std::string head = "fcurves 1\nunits mm\n";
  const std::string tail = "curves 0\nend\n";
  const Feather f = parse_fcurves(head + "medulla 0.7 8 8 9 0 0.1 0\n" + tail, "m.fcurves");
  EXPECT_FLOAT_EQ(f.medulla.ratio, 0.7f);
  EXPECT_EQ(f.medulla.sigma_s, glm::vec3(8, 8, 9));
  EXPECT_EQ(f.medulla.sigma_a, glm::vec3(0, 0.1f, 0));
  EXPECT_NE(format_fcurves(f).find("medulla 0.7 8 8 9 0 0.1 0\n"), std::string::npos);
  EXPECT_EQ(format_fcurves(Feather{}).find("medulla"), std::string::npos);
  const auto error_of = [&](const std::string& record) { return parse_error(head + record + tail, "m.fcurves"); };
  EXPECT_NE(error_of("medulla 1 8 8 8 0 0 0\n").find("m.fcurves:3:9: medulla RATIO: must be in [0, 1)"), std::string::npos)
      << error_of("medulla 1 8 8 8 0 0 0\n");
  EXPECT_NE(error_of("medulla 0.5 8 -1 8 0 0 0\n").find("medulla SIGMA_S"), std::string::npos);
  EXPECT_NE(error_of("medulla 0.5 8 8 8 0 0\n").find("medulla RATIO SIGMA_S_R"), std::string::npos);
  EXPECT_NE(error_of("medulla 0.5 8 8 8 0 0 0\nmedulla 0.5 8 8 8 0 0 0\n").find(":4:"), std::string::npos);
  Feather bad;
  bad.medulla.ratio = 0.5f;
  bad.medulla.sigma_a.y = std::nanf("");
  EXPECT_THROW(format_fcurves(bad), Error);
}

TEST(CurveFormat, DownBarbsAndTheirCoverReadWriteAndAreChecked) {
  // Down barbs (docs/curve-format.md, "Down"): their kind and the feather's cover
  // read and written back; the cover written only when not 1, and refused outside
  // (0, 1] with the place named.
  const std::string head = "fcurves 1\nunits mm\n";
  std::string curve = "curves 1\ncurve down right bspline 4 root 0.3\n";
  for (int k = 0; k < 4; ++k) curve += std::to_string(k) + " 1 0 0.25 0 0 1\n";
  const Feather f = parse_fcurves(head + "down cover 0.6\n" + curve + "end\n", "d.fcurves");
  ASSERT_EQ(f.curves.size(), 1u);
  EXPECT_EQ(f.curves[0].kind, CurveKind::Down);
  EXPECT_EQ(f.curves[0].side, VaneSide::Right);
  EXPECT_EQ(f.count(CurveKind::Down), 1u);
  EXPECT_EQ(f.count(CurveKind::Barb), 0u);
  EXPECT_FLOAT_EQ(f.down_cover, 0.6f);
  const std::string text = format_fcurves(f);
  EXPECT_NE(text.find("down cover 0.6\n"), std::string::npos);
  EXPECT_NE(text.find("curve down right bspline 4 root 0.3\n"), std::string::npos);
  EXPECT_EQ(parse_fcurves(text, "d.fcurves"), f);
  EXPECT_EQ(format_fcurves(Feather{}).find("down cover"), std::string::npos);
  const auto error_of = [&](const std::string& record) {
    return parse_error(head + record + curve + "end\n", "d.fcurves");
  };
  EXPECT_NE(error_of("down cover 0\n").find("d.fcurves:3:12: down cover: must be in (0, 1]"), std::string::npos)
      << error_of("down cover 0\n");
  EXPECT_NE(error_of("down cover 1.5\n").find("down cover"), std::string::npos);
  EXPECT_NE(error_of("down fill 0.5\n").find("d.fcurves:3:6: down: expected 'cover', found 'fill'"), std::string::npos)
      << error_of("down fill 0.5\n");
  EXPECT_NE(error_of("down cover 0.5\ndown cover 0.5\n").find(":4:"), std::string::npos);
  Feather bad = f;
  bad.down_cover = 0.0f;
  EXPECT_THROW(format_fcurves(bad), Error);
}

TEST(CurveFormat, ExtremeFloatsAreWrittenInShortestForm) {
  Feather f = samples::sample_feather(2, 4);
  f.curves[1].points[0].p = {std::numeric_limits<float>::denorm_min(), -0.0f, 1e30f};
  f.curves[1].points[0].radius = 0.1f;
  const std::string text = format_fcurves(f);
  EXPECT_NE(text.find("\n1e-45 -0 1e+30 0.1 "), std::string::npos) << text;
  EXPECT_TRUE(std::signbit(parse_fcurves(text).curves[1].points[0].p.y));
}

TEST(CurveFormat, EveryPrefixFailsCleanlyOrParsesWhole) {
  const std::string text = format_fcurves(samples::sample_feather(3, 5));
  const Feather whole = parse_fcurves(text);
  const std::size_t end_at = text.rfind("end");
  for (std::size_t n = 0; n < text.size(); ++n) {
    const std::string_view prefix(text.data(), n);
    try {
      const Feather f = parse_fcurves(prefix, "cut.fcurves");
      EXPECT_GE(n, end_at + 3) << "a prefix of " << n << " bytes parsed";
      EXPECT_EQ(f, whole);
    } catch (const Error& e) {
      EXPECT_LT(n, end_at + 3);
      EXPECT_GE(e.where().line, 1);
      EXPECT_GE(e.where().column, 1);
    }
  }
}

TEST(CurveFormat, MutatedFilesNeverCrash) {
  const std::string text = format_fcurves(samples::sample_feather(4, 5));
  std::mt19937_64 rng(7);
  const char alphabet[] = "0123456789.-+e \n\t#\"\\abcdefghijklmnopqrstuvwxyz\x01\xff";
  int errors = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string m = text;
    const int edits = 1 + int(rng() % 4);
    for (int k = 0; k < edits; ++k) {
      const std::size_t at = rng() % m.size();
      switch (rng() % 3) {
        case 0:
          m[at] = alphabet[rng() % (sizeof alphabet - 1)];
          break;
        case 1:
          m.erase(at, 1 + rng() % 8);
          break;
        default:
          m.insert(at, 1, alphabet[rng() % (sizeof alphabet - 1)]);
          break;
      }
      if (m.empty()) m.push_back('x');
    }
    try {
      const Feather f = parse_fcurves(m, "mutant.fcurves");
      // Whatever parses must be a valid feather that writes and reads back.
      EXPECT_NO_THROW(validate_feather(f));
      EXPECT_EQ(parse_fcurves(format_fcurves(f)), f);
    } catch (const Error& e) {
      ++errors;
      EXPECT_GE(e.where().line, 1) << e.what();
    }
  }
  EXPECT_GT(errors, 1000);  // the mutations mostly do break the file
}

TEST(CurveFormat, LyingCountsDoNotAllocate) {
  // 2^64-1 curves and 10^12 points declared in a few hundred bytes: the reader
  // must fail on the text, not on memory (bad_alloc would escape EXPECT_THROW's type).
  EXPECT_THROW(parse_fcurves(with_line(8, "curves 18446744073709551615")), Error);
  EXPECT_THROW(parse_fcurves(with_line(9, "curve shaft none bspline 18446744073709551615 root 0")), Error);
  EXPECT_THROW(parse_fcurves(with_line(6, kBase[5].substr(0, kBase[5].find(" 20")) + " 99999999999" +
                                              kBase[5].substr(kBase[5].find(" ramus")))),
               Error);
}

TEST(CurveFormat, WriterRejectsInvalidFeathers) {
  const Feather good = samples::sample_feather(2, 4);
  EXPECT_NO_THROW(validate_feather(good));
  auto broken = [&](auto edit) {
    Feather f = good;
    edit(f);
    return f;
  };
  const std::vector<Feather> bad = {
      broken([](Feather& f) { f.units = "cm"; }),
      broken([](Feather& f) { f.curves[1].points.resize(3); }),
      broken([](Feather& f) { f.curves[1].points[0].p.x = std::nanf(""); }),
      broken([](Feather& f) { f.curves[1].points[0].radius = -1; }),
      broken([](Feather& f) {
        f.curves[1].points[0].n = {0, 0, 0};
      }),
      broken([](Feather& f) {
        f.curves[1].points[0].n = {0, 0, 2};
      }),
      broken([](Feather& f) { f.curves[1].side = VaneSide::None; }),
      broken([](Feather& f) { f.curves[0].side = VaneSide::Left; }),
      broken([](Feather& f) { f.curves[1].kind = CurveKind::Shaft; }),
      broken([](Feather& f) { f.curves[1].root = 1.5f; }),
      broken([](Feather& f) { f.provenance.source = "two\nlines"; }),
      broken([](Feather& f) { f.albedo.texture = "a.png"; }),  // empty rectangle
      broken([](Feather& f) { f.left.elevation_deg = 0; }),
      broken([](Feather& f) { f.right.hooked_fraction = 2; }),
      broken([](Feather& f) { f.left.ramus_radius = std::numeric_limits<float>::infinity(); }),
  };
  for (std::size_t i = 0; i < bad.size(); ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    EXPECT_THROW(format_fcurves(bad[i]), Error);
  }
}

TEST(CurveFormat, FilesRoundTripAndNameThemselvesInErrors) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("plumage_curve_format_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Feather f = samples::sample_feather(6, 5);
  write_fcurves(dir / "f.fcurves", f);
  EXPECT_EQ(read_fcurves(dir / "f.fcurves"), f);
  write_file_atomic(dir / "bad.fcurves", with_line(2, "units cm"));
  try {
    read_fcurves(dir / "bad.fcurves");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, (dir / "bad.fcurves").string());
    EXPECT_EQ(e.where().line, 2);
  }
  EXPECT_THROW(read_fcurves(dir / "missing.fcurves"), Error);
  // A feather the writer refuses leaves the old file untouched.
  Feather bad = f;
  bad.curves[1].points[0].radius = -1;
  EXPECT_THROW(write_fcurves(dir / "f.fcurves", bad), Error);
  EXPECT_EQ(read_fcurves(dir / "f.fcurves"), f);
  fs::remove_all(dir);
}

TEST(CurveFormat, SpecExampleParses) {
  // The first code block of docs/curve-format.md is a complete file.
  const std::string doc = read_file(std::string(PLUMAGE_SOURCE_DIR) + "/docs/curve-format.md");
  const std::size_t open = doc.find("```\n");
  const std::size_t close = doc.find("```\n", open + 4);
  ASSERT_NE(close, std::string::npos);
  const Feather f = parse_fcurves(doc.substr(open + 4, close - open - 4), "curve-format.md");
  EXPECT_EQ(f.curves.size(), 2u);
  EXPECT_EQ(f.provenance.source, "preset:osprey-covert");
  EXPECT_EQ(f.albedo.texture, "albedo.png");
  EXPECT_EQ(f.right.elevation_deg, 42.5f);
  EXPECT_EQ(parse_fcurves(format_fcurves(f)), f);
}

TEST(CurveFormat, ShaftColoursAlongTheShaftReadBackAndAreBounded) {
  Feather f;
  f.albedo.shaft = {glm::vec3(0.9f, 0.85f, 0.8f), glm::vec3(0.05f, 0.04f, 0.03f), glm::vec3(0.1f)};
  const Feather back = parse_fcurves(format_fcurves(f), "shaft.fcurves");
  EXPECT_EQ(back.albedo.shaft, f.albedo.shaft);
  // One colour more than kMaxShaftColours is refused, naming the first extra number.
  std::string line = "albedo shaft";
  for (std::size_t k = 0; k <= kMaxShaftColours; ++k) line += " 0.5 0.5 0.5";
  const std::string text = "fcurves 1\nunits mm\n" + line + "\ncurves 0\n";
  try {
    parse_fcurves(text, "many.fcurves");
    FAIL() << "accepted " << kMaxShaftColours + 1 << " shaft colours";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("many.fcurves:3:" + std::to_string(14 + 12 * kMaxShaftColours)),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("more than 256 colours"), std::string::npos) << e.what();
  }
  Feather too_many;
  too_many.albedo.shaft.assign(kMaxShaftColours + 1, glm::vec3(0.5f));
  EXPECT_THROW(format_fcurves(too_many), Error) << "the writer refuses what the reader would";
}
