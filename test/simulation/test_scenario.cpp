#include <string>
#include <utility>
#include <vector>

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

TEST(Scenario, EveryHeldOutKindLoadsWithItsAppearance) {
  const std::vector<std::string> kinds = {
      "rand_even_static",  "rand_uneven_lamps", "rand_fast", "rand_packed",     "rand_people",
      "rand_flicker_jpeg", "rand_bayer",        "rand_ssl",  "rand_wide_angle", "rand_bayer_ssl"};
  for (const auto& name : kinds) {
    SCOPED_TRACE(name);
    const auto s = loadScenario(kScenarios + name + ".yaml");
    EXPECT_EQ(s.name, name);
    // Tuning seeds are below 100; held-out ones (>= 9000) are given on the command line.
    EXPECT_LT(s.seed, 100u);
    EXPECT_GT(s.appearance.marker_albedo_spread, 0.0);
    EXPECT_GT(s.appearance.carpet_fibre, 0.0);
  }
  const auto lamps = loadScenario(kScenarios + "rand_uneven_lamps.yaml");
  EXPECT_DOUBLE_EQ(lamps.lighting.uneven_ratio, 3.0);
  EXPECT_DOUBLE_EQ(lamps.appearance.lamp_drift, 0.3);
  const auto wide = loadScenario(kScenarios + "rand_wide_angle.yaml");
  EXPECT_DOUBLE_EQ(wide.lens.k1, -0.30);
  EXPECT_DOUBLE_EQ(wide.lens.tilt_deg, 5.0);
  EXPECT_DOUBLE_EQ(wide.appearance.vignetting, 0.4);
  const auto flicker = loadScenario(kScenarios + "rand_flicker_jpeg.yaml");
  EXPECT_DOUBLE_EQ(flicker.lighting.flicker, 0.15);
  EXPECT_EQ(flicker.sensor.jpeg_quality, 80);
  EXPECT_TRUE(flicker.appearance.demosaic);
  EXPECT_GT(loadScenario(kScenarios + "rand_people.yaml").appearance.distractors, 0);
}

TEST(Scenario, AppearanceOutOfRangeIsAnError) {
  EXPECT_NE(errorOf("appearance: {vignetting: 1.0}\n").find("vignetting"), std::string::npos);
  EXPECT_NE(errorOf("appearance: {lamps: 40}\n").find("lamps"), std::string::npos);
  EXPECT_NE(errorOf("appearance: {demosaic: true}\n").find("demosaic"), std::string::npos);
  EXPECT_NE(errorOf("appearance: {colour_temperature: 3000}\n").find("unknown key"), std::string::npos);
  EXPECT_NE(errorOf("appearance: {ball_shading: 1.5}\n").find("ball_shading"), std::string::npos);
  EXPECT_NE(errorOf("appearance: {ball_gloss: -0.1}\n").find("ball_gloss"), std::string::npos);
  EXPECT_DOUBLE_EQ(parseScenario("appearance: {ball_gloss: 0.7}", "g").appearance.ball_gloss, 0.7);
  EXPECT_NE(errorOf("lens: {k1: -0.5}\n").find("k1"), std::string::npos);
  EXPECT_NE(errorOf("lens: {tilt_deg: 20}\n").find("tilt_deg"), std::string::npos);
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

TEST(Scenario, NamesItsCameraLayout) {
  EXPECT_EQ(parseScenario("", "empty").cameras, 2);
  EXPECT_NE(errorOf("cameras: 0\n").find("cameras must be in 1..8"), std::string::npos);
  EXPECT_NE(errorOf("cameras: 9\n").find("cameras must be in 1..8"), std::string::npos);
  const auto four = loadScenario(kScenarios + "div_a_four_cameras.yaml");
  EXPECT_EQ(four.cameras, 4);
  EXPECT_EQ(four.field, "div_a");
  const auto two = loadScenario(kScenarios + "div_a_two_cameras.yaml");
  EXPECT_EQ(two.cameras, 2);
  EXPECT_EQ(two.width, 2448);
  EXPECT_DOUBLE_EQ(two.fps, 75.0);
  for (const auto* s : {&four, &two}) {
    EXPECT_EQ(s->blue_robots, 11);
    EXPECT_LE(s->blue_robots, patternSetByName(s->pattern).maxRobotsPerTeam());
  }
}

// Values that once passed: duplicate keys (yaml-cpp keeps the first), NaN motion, sizes and
// counts that hang or try to allocate tens of GB.
TEST(Scenario, DuplicateKeysNanAndUnboundedSizesAreErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"fps: 30\nfps: 60\n", "duplicate key 'fps'"},
      {"motion: {robot_max_speed: 1, robot_max_speed: 2}\n", "duplicate key 'motion.robot_max_speed'"},
      {"motion: {robot_max_speed: .nan}\n", "'motion.robot_max_speed' must be a finite number"},
      {"lighting: {brightness: .inf}\n", "'lighting.brightness' must be a finite number"},
      {"width: 100000\nheight: 100000\n", "in 64..16384"},
      {"width: 2\nheight: 2\n", "in 64..16384"},
      {"balls: 2000000000\n", "balls must be at most"},
      {"blue_robots: 1000\n", "at most 64"},
      {"sensor: {blur_samples: 100000}\n", "sensor.blur_samples in 1..64"},
  };
  for (const auto& [text, message] : cases) {
    const std::string e = errorOf(text);
    EXPECT_NE(e.find("s.yaml"), std::string::npos) << text;
    EXPECT_NE(e.find(message), std::string::npos) << text << " -> " << e;
  }
  // make_scenario's --width/--height go through the same check.
  ScenarioConfig s = parseScenario("", "default");
  s.width = 1;
  EXPECT_THROW(checkScenario(s, "--width"), std::runtime_error);
  s.width = 641;
  EXPECT_THROW(checkScenario(s, "--width"), std::runtime_error);
  s.width = 640;
  EXPECT_NO_THROW(checkScenario(s, "--width"));
}
