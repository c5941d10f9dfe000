#include "soccer_vision/ros/field_markers.h"

#include <cmath>
#include <string>

#include <geometry_msgs/Point.h>
#include <std_msgs/ColorRGBA.h>

#include "soccer_vision/ros/detection_conversions.h"

namespace soccer_vision {
namespace {

std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

geometry_msgs::Point point(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

visualization_msgs::Marker marker(const std_msgs::Header& header, const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  return m;
}

void setYaw(visualization_msgs::Marker& m, double yaw) {
  m.pose.orientation.z = std::sin(yaw / 2);
  m.pose.orientation.w = std::cos(yaw / 2);
}

}  // namespace

visualization_msgs::MarkerArray fieldMarkers(const FieldGeometry& field, const std::string& frame) {
  std_msgs::Header header;
  header.frame_id = frame;
  visualization_msgs::MarkerArray out;

  auto carpet = marker(header, "field", 0, visualization_msgs::Marker::CUBE);
  carpet.scale.x = field.length + 2 * field.boundary;
  carpet.scale.y = field.width + 2 * field.boundary;
  carpet.scale.z = 0.002;
  carpet.pose.position.z = -0.002;
  carpet.color = rgba(0.10f, 0.40f, 0.12f);
  out.markers.push_back(carpet);

  auto lines = marker(header, "field", 1, visualization_msgs::Marker::LINE_LIST);
  lines.scale.x = std::max(field.line_width, 0.02);  // thin lines vanish at rviz distances
  lines.color = rgba(1, 1, 1);
  for (const LineSegment& s : field.lines()) {
    lines.points.push_back(point(s.a.x(), s.a.y(), 0.001));
    lines.points.push_back(point(s.b.x(), s.b.y(), 0.001));
  }
  out.markers.push_back(lines);

  int id = 2;
  for (const CircleArc& c : field.circles()) {
    auto circle = marker(header, "field", id++, visualization_msgs::Marker::LINE_STRIP);
    circle.scale.x = lines.scale.x;
    circle.color = lines.color;
    for (const Eigen::Vector2d& p : c.points(72)) circle.points.push_back(point(p.x(), p.y(), 0.001));
    out.markers.push_back(circle);
  }
  return out;
}

void appendGameMarkers(const RobotPoseArray& robots, const BallPoseArray& balls, const MarkerStyle& style,
                       visualization_msgs::MarkerArray& out) {
  const ros::Duration lifetime(style.lifetime);
  for (const RobotPose& r : robots.robots) {
    const bool blue = r.team == RobotPose::TEAM_BLUE;
    const int id = (blue ? 0 : 256) + r.id;
    const double height = heightOf(style.robot_height, blue ? Team::Blue : Team::Yellow);
    const float alpha = r.visible ? 1.0f : 0.4f;
    std_msgs::Header header = robots.header;

    auto body = marker(header, "robots", id, visualization_msgs::Marker::CYLINDER);
    body.pose.position = point(r.x, r.y, height / 2);
    body.scale.x = body.scale.y = 2 * style.robot_radius;
    body.scale.z = height;
    body.color = blue ? rgba(0.1f, 0.35f, 1.0f, alpha) : rgba(1.0f, 0.85f, 0.0f, alpha);
    body.lifetime = lifetime;
    out.markers.push_back(body);

    auto text = marker(header, "robot_ids", id, visualization_msgs::Marker::TEXT_VIEW_FACING);
    text.pose.position = point(r.x, r.y, height + 0.12);
    text.scale.z = 0.15;
    text.color = rgba(1, 1, 1, alpha);
    text.text =
        r.id == kNoRobotId ? (blue ? "B" : "Y") : std::string(blue ? "B" : "Y") + std::to_string(r.id);
    text.lifetime = lifetime;
    out.markers.push_back(text);

    if (std::isfinite(r.theta)) {
      auto arrow = marker(header, "robot_headings", id, visualization_msgs::Marker::ARROW);
      arrow.pose.position = point(r.x, r.y, height + 0.01);
      setYaw(arrow, r.theta);
      arrow.scale.x = 2 * style.robot_radius;  // length
      arrow.scale.y = 0.03;
      arrow.scale.z = 0.03;
      arrow.color = rgba(1, 1, 1, alpha);
      arrow.lifetime = lifetime;
      out.markers.push_back(arrow);
    }
  }
  int ball_id = 0;
  for (const BallPose& b : balls.balls) {
    auto sphere = marker(balls.header, "balls", ball_id++, visualization_msgs::Marker::SPHERE);
    sphere.pose.position = point(b.x, b.y, b.z);
    // Drawn at 3x so it stays visible from above the whole field.
    sphere.scale.x = sphere.scale.y = sphere.scale.z = 6 * style.ball_radius;
    sphere.color = rgba(1.0f, 0.45f, 0.0f, b.visible ? 1.0f : 0.4f);
    sphere.lifetime = lifetime;
    out.markers.push_back(sphere);
  }
}

void appendOutlineMarkers(const std::vector<std::vector<Eigen::Vector3d>>& outlines,
                          const std_msgs::Header& header, double lifetime,
                          visualization_msgs::MarkerArray& out) {
  int id = 0;
  for (const auto& outline : outlines) {
    if (outline.empty()) continue;
    auto strip = marker(header, "search_windows", id++, visualization_msgs::Marker::LINE_STRIP);
    strip.scale.x = 0.01;
    strip.color = rgba(0.9f, 0.2f, 0.9f, 0.8f);
    strip.lifetime = ros::Duration(lifetime);
    for (const auto& p : outline) strip.points.push_back(point(p.x(), p.y(), p.z()));
    strip.points.push_back(strip.points.front());
    out.markers.push_back(strip);
  }
}

}  // namespace soccer_vision
