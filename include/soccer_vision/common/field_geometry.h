// Field dimensions and markings (the paper's: 9 x 6 m, 0.3 m boundary, 10 mm lines).
// Frame `field`: origin at the centre point, x along the length, y along the width, z up.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace soccer_vision {

struct LineSegment {
  Eigen::Vector2d a, b;
};

struct CircleArc {
  Eigen::Vector2d centre;
  double radius;
};

struct FieldGeometry {
  double length = 9.0;         // m, playing area along x
  double width = 6.0;          // m, playing area along y
  double boundary = 0.3;       // m, carpet outside the lines
  double line_width = 0.010;   // m
  double centre_radius = 0.5;  // m, centre circle
  double defense_depth = 1.0;  // m, defence area depth (along x)
  double defense_width = 2.0;  // m, defence area width (along y)
  double goal_width = 1.0;     // m, inner width of the goal mouth
  double goal_depth = 0.18;    // m

  double halfLength() const { return length / 2; }
  double halfWidth() const { return width / 2; }

  // All straight white lines (centre lines of the painted strips).
  std::vector<LineSegment> lines() const;
  // All white circles.
  std::vector<CircleArc> circles() const;
  // Line intersections and other well-defined points on the carpet (z = 0),
  // used for field calibration (field_points.yaml).
  std::vector<Eigen::Vector3d> landmarks() const;
  // True when (x, y) is on the carpet: playing area plus boundary (plus margin).
  bool onCarpet(double x, double y, double margin = 0.0) const;
};

}  // namespace soccer_vision
