// Field dimensions and markings, as configuration (config/fields/*.yaml): the built-in
// Division B field of the paper (9 x 6 m, the default) and Division A (12 x 9 m), or a
// custom file that lists its own lines and arcs. Every stage that knows the field (renderer,
// identification's on-carpet test, ball plausibility, landmarks, field calibration, rviz
// markers, evaluation) takes it from here.
// Frame `field`: origin at the centre point, x along the length, y along the width, z up.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace soccer_vision {

// A painted straight line (the centre line of the strip). Names follow the SSL-Vision
// geometry ("TopTouchLine", "LeftPenaltyStretch", ...; free text in custom files).
struct LineSegment {
  Eigen::Vector2d a, b;
  std::string name;

  // Distance of p from the segment (from a when it has no length).
  double distance(const Eigen::Vector2d& p) const;
};

// A painted circle or arc, counter-clockwise from angle a1 to a2 [rad] (a full circle: 0, 2 pi).
struct CircleArc {
  Eigen::Vector2d centre;
  double radius;
  std::string name;
  double a1 = 0.0;
  double a2 = 2 * 3.14159265358979323846;

  bool fullCircle() const;
  // Distance of p from the arc's curve.
  double distance(const Eigen::Vector2d& p) const;
  // segments + 1 points along the arc from a1 to a2 (for drawing it as a polyline).
  std::vector<Eigen::Vector2d> points(int segments) const;
};

struct FieldGeometry {
  std::string name = "div_b";
  double length = 9.0;               // m, playing area along x
  double width = 6.0;                // m, playing area along y
  double boundary = 0.3;             // m, carpet outside the lines
  double line_width = 0.010;         // m
  double centre_radius = 0.5;        // m, centre circle
  double penalty_area_depth = 1.0;   // m, along x
  double penalty_area_width = 2.0;   // m, along y
  double goal_width = 1.0;           // m, inner width of the goal mouth
  double goal_depth = 0.18;          // m
  double goal_height = 0.155;        // m
  double penalty_mark_distance = 6;  // m, from the goal centre
  bool centre_line = false;          // a line from goal to goal along x (SSL "CenterLine")
  // Custom markings: when set, they replace the standard ones generated from the dimensions.
  std::vector<LineSegment> custom_lines;
  std::vector<CircleArc> custom_arcs;

  double halfLength() const { return length / 2; }
  double halfWidth() const { return width / 2; }
  // Half extents of the carpet (playing area plus boundary): where its walls stand.
  double carpetHalfLength() const { return halfLength() + boundary; }
  double carpetHalfWidth() const { return halfWidth() + boundary; }

  // All straight white lines.
  std::vector<LineSegment> lines() const;
  // All white circles and arcs.
  std::vector<CircleArc> circles() const;
  // Line intersections and other well-defined points on the carpet (z = 0),
  // used for field calibration (field_points.yaml).
  std::vector<Eigen::Vector3d> landmarks() const;
  // Distance of p from the nearest painted line's or arc's centre line.
  double distanceToMarkings(const Eigen::Vector2d& p) const;
  // Distance of p from the carpet's outer edge, where its walls stand (inside or out).
  double distanceToCarpetEdge(const Eigen::Vector2d& p) const;
  // True when (x, y) is on the carpet: playing area plus boundary (plus margin).
  bool onCarpet(double x, double y, double margin = 0.0) const;
  // True when (x, y) is inside the playing area (within the outer edge of the lines, plus margin).
  bool inPlayingArea(double x, double y, double margin = 0.0) const;

  // Built-in definitions equal to config/fields/div_b.yaml and div_a.yaml.
  static FieldGeometry divB();
  static FieldGeometry divA();
};

// Parses a field YAML document (config/fields/*.yaml: see docs/formats.md). Unknown or
// repeated keys, non-finite or out-of-range values are errors: throws std::runtime_error
// naming the source and the key.
FieldGeometry parseFieldGeometry(const std::string& yaml_text, const std::string& source_name);
FieldGeometry loadFieldGeometry(const std::string& path);
// "div_b", "div_a" (built in) or a path to a YAML file; "" is div_b.
FieldGeometry fieldGeometryByName(const std::string& name_or_path);

}  // namespace soccer_vision
