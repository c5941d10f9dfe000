// Marker patterns as data (config/patterns/*.yaml): where each coloured tag sits on a
// robot's top, per team and per id. Robot frame: x forward (heading), y left, metres.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/color_class.h"

namespace soccer_vision {

struct MarkerShape {
  enum class Kind { Disc, Rect };
  Kind kind = Kind::Disc;
  double x = 0, y = 0;            // centre in the robot frame, m
  double radius = 0;              // Disc, m
  double size_x = 0, size_y = 0;  // Rect: full extent along robot x and y, m
};

// The marker plane of each team's robots, m (index: Team): how every stage that projects
// robots keeps the pattern's heights (PatternSet::heights), read through heightOf.
using TeamHeights = std::array<double, 2>;
inline double heightOf(const TeamHeights& heights, Team team) {
  return heights[static_cast<std::size_t>(team)];
}

struct ColoredMarker {
  MarkerShape shape;
  ColorClass color = ColorClass::None;
};

struct PatternSet {
  std::string name;
  double robot_radius = 0.090;  // m
  // m, the marker plane of both teams unless `team_height` overrides it for a team. Teams'
  // robots differ in height; a wrong plane shifts positions by parallax (a 2 cm error at
  // 3 m from the principal axis, camera 3 m high: 2 cm). Read it through height(team).
  double robot_height = 0.150;
  std::array<std::optional<double>, 2> team_height;  // m, per Team (index: Team value)
  MarkerShape team_marker;                           // drawn in the team colour
  std::vector<MarkerShape> slots;                    // id markers (may be empty: team-marker-only mode)
  // ids[id][slot] = colour of that slot for robot `id`.
  std::vector<std::vector<ColorClass>> ids;

  // Team-marker-only sets have no ids; they allow as many robots as the SSL pattern.
  int maxRobotsPerTeam() const { return ids.empty() ? 16 : static_cast<int>(ids.size()); }
  // The marker plane of `team`'s robots, m.
  double height(Team team) const {
    const auto& own = team_height[static_cast<std::size_t>(team)];
    return own ? *own : robot_height;
  }
  TeamHeights heights() const { return {height(Team::Blue), height(Team::Yellow)}; }
  // Every marker of robot (team, id), team marker first.
  std::vector<ColoredMarker> markers(Team team, int id) const;

  // Built-in definitions equal to config/patterns/{two_tag,ssl,team_only}.yaml.
  static PatternSet twoTag();
  static PatternSet ssl();
  static PatternSet teamOnly();
};

// Points on the outlines of robot (team, id)'s markers in `field` (each rectangle's corners,
// 8 points on each disc's rim) on its team's marker plane, the robot at (x, y) heading
// `theta`. A robot is visible in an image when all of them are in it: what the ground
// truth (FieldRenderer::robotVisible) and the measured rate count.
std::vector<Eigen::Vector3d> markerOutlinePoints(const PatternSet& patterns, Team team, int id, double x,
                                                 double y, double theta);
// The same points of one marker shape (robot frame) on the plane z, appended to `points`.
void appendShapeOutline(const MarkerShape& shape, double x, double y, double theta, double z,
                        std::vector<Eigen::Vector3d>& points);

// Parses a pattern YAML document; throws std::runtime_error with a clear message.
PatternSet parsePatternSet(const std::string& yaml_text, const std::string& source_name);
PatternSet loadPatternSet(const std::string& path);
// "two_tag", "ssl", "team_only" (built in) or a path to a YAML file.
PatternSet patternSetByName(const std::string& name_or_path);

}  // namespace soccer_vision
