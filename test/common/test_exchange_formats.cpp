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
