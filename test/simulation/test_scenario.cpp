#include <gtest/gtest.h>

#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/simulation/scenario.h"

using namespace soccer_vision;

namespace {
const std::string kScenarios = std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/";

std::string errorOf(const std::string& text) {
  try {
    parseScenario(text, "s.yaml");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Scenario, EmptyDocumentIsTheEmbeddedDefault) {
  const auto s = parseScenario("", "empty");
  EXPECT_EQ(s.pattern, "two_tag");
  EXPECT_EQ(s.blue_robots, 5);
  EXPECT_EQ(s.yellow_robots, 5);
  EXPECT_EQ(s.width, 1280);
  EXPECT_DOUBLE_EQ(s.fps, 60.0);
}

TEST(Scenario, EveryPresetLoadsAndItsPatternExists) {
  const std::vector<std::string> required = {"even_static", "uneven_drift",  "fast_motion",
                                             "crowded",     "flicker_noise", "ssl_pattern"};
  for (const auto& name : required) {
    SCOPED_TRACE(name);
    const auto s = loadScenario(kScenarios + name + ".yaml");
    EXPECT_EQ(s.name, name);
    const auto p = patternSetByName(s.pattern);
    EXPECT_LE(s.blue_robots, p.maxRobotsPerTeam());
    EXPECT_LE(s.yellow_robots, p.maxRobotsPerTeam());
  }
  const auto fast = loadScenario(kScenarios + "fast_motion.yaml");
  EXPECT_DOUBLE_EQ(fast.motion.robot_max_speed, 5.0);
  EXPECT_DOUBLE_EQ(fast.motion.ball_max_speed, 15.0);
  EXPECT_GT(fast.sensor.blur_samples, 1);
  const auto crowded = loadScenario(kScenarios + "crowded.yaml");
  EXPECT_EQ(crowded.blue_robots + crowded.yellow_robots, 32);
  EXPECT_EQ(loadScenario(kScenarios + "flicker_noise.yaml").sensor.bayer, "rggb");
}

TEST(Scenario, TyposAndOutOfRangeValuesAreErrors) {
  EXPECT_NE(errorOf("fsp: 30\n").find("unknown key 'fsp'"), std::string::npos);
  EXPECT_NE(errorOf("lighting: {uneven: 2}\n").find("unknown key 'lighting.uneven'"), std::string::npos);
  EXPECT_NE(errorOf("fps: fast\n").find("wrong type"), std::string::npos);
  EXPECT_NE(errorOf("motion: {robot_max_speed: 7}\n").find("robot_max_speed"), std::string::npos);
  EXPECT_NE(errorOf("motion: {ball_max_speed: 20}\n").find("ball_max_speed"), std::string::npos);
  EXPECT_NE(errorOf("sensor: {bayer: rgbg}\n").find("bayer"), std::string::npos);
  EXPECT_NE(errorOf("lighting: {uneven_ratio: 0.5}\n").find("uneven_ratio"), std::string::npos);
  EXPECT_NE(errorOf("width: 641\n").find("even"), std::string::npos);
  EXPECT_NE(errorOf("{{{").find("invalid YAML"), std::string::npos);
  EXPECT_THROW(loadScenario("/nonexistent.yaml"), std::runtime_error);
}

TEST(Scenario, NamesItsField) {
  EXPECT_EQ(parseScenario("", "empty").field, "div_b");
  EXPECT_EQ(parseScenario("field: div_a", "a").field, "div_a");
  EXPECT_THROW(parseScenario("field: [1]", "bad"), std::runtime_error);
}
