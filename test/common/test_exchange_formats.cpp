#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "soccer_vision/common/exchange_formats.h"

using namespace soccer_vision;

TEST(ExchangeFormats, JsonLineMatchesDesignExample) {
  const auto f =
      parseJsonLine(R"({"stamp": 1700000000.016667, "robots": [{"team": "blue", "id": 3, "x": 1.204,)"
                    R"( "y": -0.551, "theta": 1.571}], "balls": [{"x": 0.120, "y": 0.003}]})");
  EXPECT_DOUBLE_EQ(f.stamp, 1700000000.016667);
  ASSERT_EQ(f.robots.size(), 1u);
  EXPECT_EQ(f.robots[0].team, Team::Blue);
  EXPECT_EQ(f.robots[0].id, 3);
  EXPECT_DOUBLE_EQ(f.robots[0].theta, 1.571);
  EXPECT_FALSE(f.robots[0].visible);
  ASSERT_EQ(f.balls.size(), 1u);
  EXPECT_DOUBLE_EQ(f.balls[0].y, 0.003);
}

TEST(ExchangeFormats, JsonLinesRoundTripWithOptionalFields) {
  FrameRecord f;
  f.stamp = 1700000000.016667;
  RobotRecord r;
  r.team = Team::Yellow;
  r.id = 15;
  r.x = -4.1234;
  r.y = 2.5;
  r.theta = -3.1;
  r.visible = false;
  f.robots.push_back(r);
  BallRecord b;
  b.x = 0.12;
  b.y = 0.003;
  b.confidence = 0.75;
  f.balls.push_back(b);
  const std::string path = ::testing::TempDir() + "/frames.jsonl";
  writeJsonLines(path, {f, f});
  const auto back = readJsonLines(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_NEAR(back[1].stamp, f.stamp, 1e-6);
  EXPECT_EQ(back[1].robots[0].team, Team::Yellow);
  EXPECT_EQ(back[1].robots[0].id, 15);
  EXPECT_DOUBLE_EQ(back[1].robots[0].x, -4.1234);
  EXPECT_EQ(back[1].robots[0].visible, std::optional<bool>(false));
  EXPECT_EQ(back[1].balls[0].confidence, std::optional<double>(0.75));
  std::remove(path.c_str());
}

TEST(ExchangeFormats, BadJsonLineNamesTheLine) {
  const std::string path = ::testing::TempDir() + "/bad.jsonl";
  writeTextFile(
      path, "{\"stamp\": 1, \"robots\": [], \"balls\": []}\n{\"stamp\": 2, \"robots\": [{\"team\": \"red\"");
  try {
    readJsonLines(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.jsonl:2"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(ExchangeFormats, ColorSamplesRoundTripInDesignFormat) {
  const auto s = parseColorSamples(
      "pink:\n  - [[612, 400], [620, 400], [620, 408], [612, 408]]\n"
      "orange:\n  - [[100.5, 200.0], [104.0, 203.5], [100.5, 207.0], [97.0, 203.5]]\n",
      "s.yaml");
  ASSERT_EQ(s.at(ColorClass::Pink).size(), 1u);
  EXPECT_EQ(s.at(ColorClass::Pink)[0].size(), 4u);
  EXPECT_DOUBLE_EQ(s.at(ColorClass::Orange)[0][3].x(), 97.0);
  const auto back = parseColorSamples(toYaml(s), "round trip");
  EXPECT_EQ(back.at(ColorClass::Orange)[0][2], s.at(ColorClass::Orange)[0][2]);
  EXPECT_THROW(parseColorSamples("magenta:\n  - [[0, 0], [1, 0], [1, 1]]\n", "x"), std::runtime_error);
  EXPECT_THROW(parseColorSamples("pink:\n  - [[0, 0], [1, 0]]\n", "x"), std::runtime_error);
  EXPECT_THROW(parseColorSamples("pink:\n  - [[0, 0, 1], [1, 0], [1, 1]]\n", "x"), std::runtime_error);
}

TEST(ExchangeFormats, FieldCorrespondencesRoundTripAndIgnoreUnknownKeys) {
  const auto p = parseFieldCorrespondences(
      "camera: 0\npoints:\n  - {pixel: [10.5, 20], field: [4.5, -3, 0], note: corner}\n", "f.yaml");
  ASSERT_EQ(p.size(), 1u);
  EXPECT_DOUBLE_EQ(p[0].pixel.x(), 10.5);
  EXPECT_DOUBLE_EQ(p[0].field.y(), -3.0);
  const auto back = parseFieldCorrespondences(toYaml(p), "round trip");
  EXPECT_EQ(back[0].field, p[0].field);
  EXPECT_THROW(parseFieldCorrespondences("points:\n  - {pixel: [1], field: [0, 0, 0]}\n", "x"),
               std::runtime_error);
  EXPECT_THROW(parseFieldCorrespondences("pts: []\n", "x"), std::runtime_error);
}

// The message of what `parse` throws (empty when it does not throw).
template <typename Parse>
std::string errorOf(Parse parse) {
  try {
    parse();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// What the tools print of a sample file: the classes with polygons, in class order.
TEST(ExchangeFormats, SampledClassNamesListTheClassesWithPolygons) {
  ColorSamples s = parseColorSamples(
      "pink:\n  - [[612, 400], [620, 400], [620, 408]]\n"
      "blue:\n  - [[1, 1], [5, 1], [5, 5]]\n",
      "s.yaml");
  s[ColorClass::Yellow];  // no polygon: not sampled
  EXPECT_EQ(sampledClassNames(s), "blue, pink");
  EXPECT_EQ(sampledClassNames({}), "");
  // The names in the order given (colour_class.h), as the calibration's warnings list them.
  EXPECT_EQ(colorClassNames({ColorClass::Purple, ColorClass::Pink}), "purple, pink");
  EXPECT_EQ(colorClassNames({}), "");
}

TEST(ExchangeFormats, ColorSamplesWithNanHugeOrDegeneratePolygonsAreRefusedNamingFileAndPolygon) {
  const auto parse = [](const std::string& text) {
    return errorOf([&] { parseColorSamples(text, "s.yaml"); });
  };
  std::string e = parse("pink:\n  - [[0, 0], [5, 0], [5, 5]]\n  - [[0, 0], [.nan, 0], [5, 5]]\n");
  EXPECT_NE(e.find("s.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("finite"), std::string::npos) << e;
  e = parse("pink:\n  - [[0, 0], [.inf, 0], [5, 5]]\n");
  EXPECT_NE(e.find("finite"), std::string::npos) << e;
  e = parse("blue:\n  - [[0, 0], [5, 0], [5, 5]]\n  - [[0, 0], [2e6, 0], [5, 5]]\n");
  EXPECT_NE(e.find("'blue' polygon 1 vertex 1"), std::string::npos) << e;
  e = parse("green:\n  - [[0, 0], [5, 5], [10, 10]]\n");  // on one line
  EXPECT_NE(e.find("'green' polygon 0 has no area"), std::string::npos) << e;
  e = parse("green:\n  - [[1, 1], [1, 1], [1, 1], [1, 1]]\n");
  EXPECT_NE(e.find("no area"), std::string::npos) << e;

  std::string many = "pink:\n  - [";
  for (std::size_t i = 0; i <= kMaxPolygonVertices; ++i) {
    const double a = 2 * M_PI * i / (kMaxPolygonVertices + 1);
    many += (i ? ", [" : "[") + std::to_string(100 + 50 * std::cos(a)) + ", " +
            std::to_string(100 + 50 * std::sin(a)) + "]";
  }
  many += "]\n";
  e = parse(many);
  EXPECT_NE(e.find(std::to_string(kMaxPolygonVertices + 1) + " vertices"), std::string::npos) << e;

  ColorSamples too_many;
  too_many[ColorClass::Pink].assign(kMaxSamplePolygons + 1, Polygon{{0, 0}, {1, 0}, {1, 1}});
  e = errorOf([&] { checkColorSamples(too_many); });
  EXPECT_NE(e.find("more than " + std::to_string(kMaxSamplePolygons)), std::string::npos) << e;
  too_many[ColorClass::Pink].resize(kMaxSamplePolygons);
  EXPECT_EQ(errorOf([&] { checkColorSamples(too_many); }), "");
}

TEST(ExchangeFormats, FieldCorrespondencesWithNanAreRefusedNamingThePoint) {
  const std::string e = errorOf([] {
    parseFieldCorrespondences(
        "points:\n  - {pixel: [1, 2], field: [0, 0, 0]}\n  - {pixel: [1, .nan], field: [0, 0, 0]}\n",
        "f.yaml");
  });
  EXPECT_NE(e.find("f.yaml: point 1: pixel must be finite"), std::string::npos) << e;
}
