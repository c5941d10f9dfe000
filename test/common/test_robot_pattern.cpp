#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/common/robot_pattern.h"

using namespace soccer_vision;

namespace {
const std::string kConfig = std::string(SOCCER_VISION_SOURCE_DIR) + "/config/patterns/";

void expectSameShape(const MarkerShape& a, const MarkerShape& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_NEAR(a.x, b.x, 1e-9);
  EXPECT_NEAR(a.y, b.y, 1e-9);
  EXPECT_NEAR(a.radius, b.radius, 1e-9);
  EXPECT_NEAR(a.size_x, b.size_x, 1e-9);
  EXPECT_NEAR(a.size_y, b.size_y, 1e-9);
}

void expectSameSet(const PatternSet& a, const PatternSet& b) {
  EXPECT_EQ(a.name, b.name);
  expectSameShape(a.team_marker, b.team_marker);
  ASSERT_EQ(a.slots.size(), b.slots.size());
  for (std::size_t i = 0; i < a.slots.size(); ++i) expectSameShape(a.slots[i], b.slots[i]);
  EXPECT_EQ(a.ids, b.ids);
  EXPECT_DOUBLE_EQ(a.height(Team::Blue), b.height(Team::Blue));
  EXPECT_DOUBLE_EQ(a.height(Team::Yellow), b.height(Team::Yellow));
}

// The message parsePatternSet throws for `text`, or "" when it parses.
std::string parseError(const std::string& text) {
  try {
    parsePatternSet(text, "test.yaml");
  } catch (const std::runtime_error& e) {
    return std::string(e.what());
  }
  return std::string();
}

}  // namespace

TEST(Patterns, TwoTagMatchesDesign) {
  const auto p = PatternSet::twoTag();
  // Team tag 80 x 30 mm, centre 20 mm behind, long side across the heading.
  EXPECT_EQ(p.team_marker.kind, MarkerShape::Kind::Rect);
  EXPECT_DOUBLE_EQ(p.team_marker.x, -0.020);
  EXPECT_DOUBLE_EQ(p.team_marker.size_y, 0.080);
  EXPECT_DOUBLE_EQ(p.team_marker.size_x, 0.030);
  // Role disc 40 mm, 45 mm ahead; ids 0..4 pink, purple, sky_blue, green, red.
  ASSERT_EQ(p.slots.size(), 1u);
  EXPECT_DOUBLE_EQ(p.slots[0].x, 0.045);
  EXPECT_DOUBLE_EQ(p.slots[0].radius, 0.020);
  ASSERT_EQ(p.maxRobotsPerTeam(), 5);
  EXPECT_EQ(p.markers(Team::Yellow, 2)[0].color, ColorClass::Yellow);
  EXPECT_EQ(p.markers(Team::Yellow, 2)[1].color, ColorClass::SkyBlue);
  EXPECT_EQ(p.markers(Team::Blue, 4)[1].color, ColorClass::Red);
}

TEST(Patterns, SslMatchesDesign) {
  const auto p = PatternSet::ssl();
  EXPECT_DOUBLE_EQ(p.team_marker.radius, 0.025);
  ASSERT_EQ(p.slots.size(), 4u);
  const double angles[] = {-60, 60, 135, -135};  // FR, FL, BL, BR
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(std::hypot(p.slots[i].x, p.slots[i].y), 0.065, 1e-12);
    EXPECT_NEAR(std::atan2(p.slots[i].y, p.slots[i].x) * 180 / M_PI, angles[i], 1e-9);
    EXPECT_DOUBLE_EQ(p.slots[i].radius, 0.020);
  }
  ASSERT_EQ(p.maxRobotsPerTeam(), 16);
  const auto g = ColorClass::Green, k = ColorClass::Pink;
  EXPECT_EQ(p.ids[0], (std::vector<ColorClass>{g, g, g, g}));
  EXPECT_EQ(p.ids[15], (std::vector<ColorClass>{k, k, k, k}));
  EXPECT_EQ(p.ids[8], (std::vector<ColorClass>{k, g, g, g}));  // front right is the MSB
  EXPECT_EQ(p.ids[1], (std::vector<ColorClass>{g, g, g, k}));  // back right is the LSB
}

TEST(Patterns, FilesEqualBuiltIns) {
  expectSameSet(loadPatternSet(kConfig + "two_tag.yaml"), PatternSet::twoTag());
  expectSameSet(loadPatternSet(kConfig + "ssl.yaml"), PatternSet::ssl());
  expectSameSet(loadPatternSet(kConfig + "team_only.yaml"), PatternSet::teamOnly());
  EXPECT_EQ(patternSetByName("ssl").ids.size(), 16u);
}

TEST(Patterns, BadFilesAreRejectedWithAClearMessage) {
  const std::string team = "team_marker: {shape: disc, x: 0, y: 0, radius: 0.025}\n";
  EXPECT_NE(parseError("[1, 2").find("invalid YAML"), std::string::npos);
  EXPECT_NE(parseError("name: x\n").find("team_marker"), std::string::npos);
  EXPECT_NE(parseError(team + "slots: [{shape: disc, x: 0.05, y: 0, radius: 0.02}]\nids: [[blue_ish]]\n")
                .find("not a marker colour"),
            std::string::npos);
  EXPECT_NE(parseError(team + "slots: [{shape: disc, x: 0.05, y: 0, radius: 0.02}]\nids: [[pink, red]]\n")
                .find("one colour per slot"),
            std::string::npos);
  EXPECT_NE(parseError(team + "slots: [{shape: disc, x: 0.05, y: 0, radius: 0.02}]\nids: [[pink], [pink]]\n")
                .find("same colours"),
            std::string::npos);
  EXPECT_NE(parseError(team + "slots: [{shape: disc, x: 0.08, y: 0, radius: 0.02}]\nids: [[pink]]\n")
                .find("exceeds"),
            std::string::npos);
  EXPECT_NE(parseError("team_marker: {shape: star, x: 0, y: 0}\n").find("'disc' or 'rect'"),
            std::string::npos);
  EXPECT_THROW(loadPatternSet("/nonexistent/pattern.yaml"), std::runtime_error);
}

// Files that once loaded as something else: NaN geometry, a robot without height, typos
// that made a team-only pattern, the ball's orange as an id colour.
TEST(Patterns, NanGeometryTyposAndOrangeIdsAreRefusedNamingTheKey) {
  const std::string team = "team_marker: {shape: disc, x: 0, y: 0, radius: 0.025}\n";
  const std::string slot = "slots: [{shape: disc, x: 0.05, y: 0, radius: 0.02}]\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"team_marker: {shape: disc, x: .nan, y: 0, radius: 0.025}\n", "'x' must be a finite number"},
      {"team_marker: {shape: disc, x: 0, y: 0, radius: .inf}\n", "'radius' must be a finite number"},
      {"robot_height: 0\n" + team, "'robot_height' must be positive"},
      {"robot_height: -0.15\n" + team, "'robot_height' must be positive"},
      {"robot_radius: .nan\n" + team, "'robot_radius' must be a finite number"},
      {team + "slot: [{shape: disc, x: 0.05, y: 0, radius: 0.02}]\nids: [[pink]]\n", "unknown key 'slot'"},
      {team + slot + "id: [[pink]]\n", "unknown key 'id'"},
      {"team_marker: {shape: disc, x: 0, y: 0, radius: 0.025, raduis: 0.02}\n", "unknown key 'raduis'"},
      {team + slot + "ids: [[orange]]\n", "'orange' is not an id colour"},
      {team + slot + "ids: [[pink], [blue]]\n", "id 1: 'blue' is not an id colour"},
  };
  for (const auto& [text, message] : cases) {
    const std::string e = parseError(text);
    EXPECT_NE(e.find("test.yaml"), std::string::npos) << text;
    EXPECT_NE(e.find(message), std::string::npos) << text << " -> " << e;
  }
  EXPECT_EQ(parseError(team + slot + "ids: [[pink], [green]]\n"), "");
}

// The marker plane: one number for both teams, or one per team (their robots differ).
TEST(Patterns, RobotHeightIsOneNumberOrOnePerTeam) {
  const std::string team = "team_marker: {shape: disc, x: 0, y: 0, radius: 0.025}\n";
  for (const PatternSet& p : {PatternSet::twoTag(), PatternSet::ssl(), PatternSet::teamOnly()}) {
    EXPECT_DOUBLE_EQ(p.height(Team::Blue), 0.150) << p.name;
    EXPECT_DOUBLE_EQ(p.height(Team::Yellow), 0.150) << p.name;
  }
  const PatternSet both = parsePatternSet("robot_height: 0.140\n" + team, "both.yaml");
  EXPECT_DOUBLE_EQ(both.height(Team::Blue), 0.140);
  EXPECT_DOUBLE_EQ(both.height(Team::Yellow), 0.140);
  const PatternSet per_team =
      parsePatternSet("robot_height: {blue: 0.148, yellow: 0.135}\n" + team, "t.yaml");
  EXPECT_DOUBLE_EQ(per_team.height(Team::Blue), 0.148);
  EXPECT_DOUBLE_EQ(per_team.height(Team::Yellow), 0.135);
  // In code: robot_height stays the height of a team without its own.
  PatternSet one = PatternSet::twoTag();
  one.team_height[static_cast<std::size_t>(Team::Yellow)] = 0.130;
  EXPECT_DOUBLE_EQ(one.height(Team::Blue), 0.150);
  EXPECT_DOUBLE_EQ(one.height(Team::Yellow), 0.130);
  // The fuzz corpus' per-team file is a valid pattern.
  const PatternSet corpus =
      loadPatternSet(std::string(SOCCER_VISION_SOURCE_DIR) + "/test/fuzz/corpus/pattern/team_heights.yaml");
  EXPECT_DOUBLE_EQ(corpus.height(Team::Blue), 0.148);
  EXPECT_DOUBLE_EQ(corpus.height(Team::Yellow), 0.135);
}

TEST(Patterns, BadRobotHeightsAreRefusedNamingTheTeam) {
  const std::string team = "team_marker: {shape: disc, x: 0, y: 0, radius: 0.025}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"robot_height: 0.7\n", "'robot_height' must be a finite number within +-0.5"},
      {"robot_height: .nan\n", "'robot_height' must be a finite number"},
      {"robot_height: tall\n", "'robot_height' is not a number"},
      {"robot_height: [0.15, 0.13]\n", "'robot_height' must be a number or a map {blue: h, yellow: h}"},
      {"robot_height:\n", "'robot_height' must be a number or a map"},
      {"robot_height: {blue: 0.15}\n", "must give both teams (missing 'yellow')"},
      {"robot_height: {yellow: 0.15}\n", "must give both teams (missing 'blue')"},
      {"robot_height: {blue: 0.15, yellow: 0.13, green: 0.1}\n", "unknown key 'green' in 'robot_height'"},
      {"robot_height: {blue: .nan, yellow: 0.13}\n", "'robot_height.blue' must be a finite number"},
      {"robot_height: {blue: 0.15, yellow: 0}\n", "'robot_height.yellow' must be positive"},
      {"robot_height: {blue: 0.15, yellow: -0.1}\n", "'robot_height.yellow' must be positive"},
      {"robot_height: {blue: 0.15, yellow: 2}\n",
       "'robot_height.yellow' must be a finite number within +-0.5"},
      {"robot_height: {blue: high, yellow: 0.13}\n", "'robot_height.blue' is not a number"},
  };
  for (const auto& [text, message] : cases) {
    const std::string e = parseError(text + team);
    EXPECT_NE(e.find("test.yaml"), std::string::npos) << text;
    EXPECT_NE(e.find(message), std::string::npos) << text << " -> " << e;
  }
}
