// rviz markers of the field and of the tracked game: field lines, robots as team-coloured
// cylinders with their id and a heading arrow, the ball as an orange sphere, and search
// window outlines. Shared by the Tracking nodelet and the tools.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <visualization_msgs/MarkerArray.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"

namespace soccer_vision {

struct MarkerStyle {
  double robot_radius = 0.090;             // m
  TeamHeights robot_height{0.150, 0.150};  // m, per team
  double ball_radius = kBallRadius;        // m
  double lifetime = 0.25;                  // s: a robot no longer published disappears after this
};

// The carpet and its white lines in `frame` (namespace "field"), stamp 0: static.
visualization_msgs::MarkerArray fieldMarkers(const FieldGeometry& field, const std::string& frame = "field");

// Robots (namespaces "robots", "robot_ids", "robot_headings") and balls ("balls") with the
// messages' stamps and frames, appended to `out`. Marker ids are stable per (team, id), so
// rviz moves a robot instead of drawing a new one; robots predicted but not measured are
// drawn translucent.
void appendGameMarkers(const RobotPoseArray& robots, const BallPoseArray& balls, const MarkerStyle& style,
                       visualization_msgs::MarkerArray& out);

// Closed outlines (field coordinates, e.g. search windows projected onto the marker
// plane), namespace "search_windows", one LINE_STRIP each.
void appendOutlineMarkers(const std::vector<std::vector<Eigen::Vector3d>>& outlines,
                          const std_msgs::Header& header, double lifetime,
                          visualization_msgs::MarkerArray& out);

}  // namespace soccer_vision
