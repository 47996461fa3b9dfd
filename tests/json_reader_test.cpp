// The one way the project reads its JSON inputs (common/json_reader.h): every error
// names the file and the place as a person reads it, and says what was expected;
// the three formats (layout.json, parameter files, light rigs) go through it.
#include <gtest/gtest.h>

#include <string>

#include "plumage/common/error.h"
#include "plumage/common/json_file.h"
#include "plumage/common/json_reader.h"
#include "plumage/renderer/dome_rig.h"

namespace plumage {
namespace {

// The message `body` throws (empty when it throws nothing).
template <class F>
std::string error_of(F&& body) {
  try {
    body();
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

const nlohmann::json kDoc = parse_json(R"({
  "shaft": {"length": 120, "bend": true, "count": 3.0, "half": 2.5},
  "leds": [{"position": [1, 2, 3]}, {"position": [1, 2]}],
  "name": "x"
})",
                                       "p.json");

TEST(JsonReader, PlacesAreWrittenAsAPersonReadsThem) {
  const JsonReader top(kDoc, "p.json");
  EXPECT_EQ(top.place(), "");
  EXPECT_EQ(top.member("shaft").member("length").place(), "shaft.length");
  const auto leds = top.member("leds").elements(2);
  EXPECT_EQ(leds[1].member("position").place(), "leds[1].position");
  EXPECT_EQ(leds[1].member("position").elements()[1].place(), "leds[1].position[1]");
  EXPECT_DOUBLE_EQ(top.member("shaft").member("length").number(0, 200), 120.0);
  EXPECT_EQ(top.member("shaft").member("count").integer(0, 10), 3);  // 3.0 is a whole number
  EXPECT_EQ(top.member("name").string(), "x");
  EXPECT_TRUE(top.member("shaft").member("bend").boolean());
  EXPECT_FALSE(top.find("missing").has_value());
}

TEST(JsonReader, ErrorsNameTheFileThePlaceAndWhatWasExpected) {
  const JsonReader top(kDoc, "p.json");
  const JsonReader shaft = top.member("shaft");
  EXPECT_EQ(error_of([&] { shaft.member("bend").number(); }), "p.json: shaft.bend: expected a number, got boolean");
  EXPECT_EQ(error_of([&] { shaft.member("length").number(0, 100); }),
            "p.json: shaft.length: value 120 is out of range; allowed [0, 100]");
  EXPECT_EQ(error_of([&] { shaft.member("length").number(200); }),
            "p.json: shaft.length: value 120 is out of range; allowed >= 200");
  EXPECT_EQ(error_of([&] { shaft.member("half").integer(0, 10); }), "p.json: shaft.half: expected an integer, got 2.5");
  EXPECT_EQ(error_of([&] { shaft.member("count").integer(4, 10); }),
            "p.json: shaft.count: value 3.0 is out of range; allowed integers [4, 10]");
  EXPECT_EQ(error_of([&] { shaft.member("width"); }), "p.json: shaft: missing key \"width\"");
  EXPECT_EQ(error_of([&] { top.member("leds").elements()[1].member("position").numbers(3); }),
            "p.json: leds[1].position: expected 3 values, got 2");
  EXPECT_EQ(error_of([&] { top.member("leds").elements(0, 3); }), "p.json: leds: expected at least 3 values, got 2");
  EXPECT_EQ(error_of([&] { top.member("name").elements(); }), "p.json: name: expected an array [...], got string");
  EXPECT_EQ(error_of([&] { top.member("leds").member("x"); }), "p.json: leds: expected an object {...}, got array");
  const JsonReader hinted(kDoc, "p.json", "see docs/x.md");
  EXPECT_EQ(error_of([&] { hinted.member("name").number(); }),
            "p.json: name: expected a number, got string (see docs/x.md)");
  const nlohmann::json array = nlohmann::json::array();
  EXPECT_EQ(error_of([&] { JsonReader(array, "a.json").expect_object(); }),
            "a.json: top level: expected an object {...}, got array");
}

TEST(JsonReader, FinishRefusesTheKeysNotAskedForWithTheNearestKnownOne) {
  const JsonReader shaft = JsonReader(kDoc, "p.json").member("shaft");
  shaft.find("length");
  shaft.find("bend");
  shaft.find("count");
  EXPECT_EQ(error_of([&] { shaft.finish(); }),
            "p.json: shaft.half: unknown key; known keys here: bend, count, length");
  shaft.find("hall");
  EXPECT_EQ(error_of([&] { shaft.finish(); }),
            "p.json: shaft.half: unknown key (did you mean 'hall'?); known keys here: bend, count, hall, length");
  shaft.has("half");
  EXPECT_EQ(error_of([&] { shaft.finish(); }), "");
  EXPECT_EQ(edit_distance("lenght", "length"), 2u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("same", "same"), 0u);
}

// The light rig reads through it: its errors name the LED.
TEST(JsonReader, ALightRigsErrorsNameTheLed) {
  const std::string two = R"({"leds": [{"position": [0, 0, 100]}, {"position": [1, 2]}]})";
  EXPECT_EQ(error_of([&] { parse_dome_rig(two, "rig.json"); }),
            "rig.json: leds[1].position: expected 3 values, got 2 (see docs/rendering.md, \"The dome rig\")");
  EXPECT_NE(error_of([&] { parse_dome_rig(R"({"leds": [{"position": [0, 0, 1]}], "led_radius": -2})", "r.json"); })
                .find("r.json: led_radius: expected a positive number of mm"),
            std::string::npos);
  EXPECT_NE(error_of([&] { parse_dome_rig(R"({"leds": [{"position": [0, 0, 1]}]})", "r.json"); })
                .find("leds[0].position: lies within one LED radius"),
            std::string::npos);
  EXPECT_EQ(parse_dome_rig(R"({"leds": [{"position": 50}], "intensity": [1, 2, 3]})", "r.json").leds.size(), 1u);
}

}  // namespace
}  // namespace plumage
