// Field geometry as configuration: the files of config/fields/ against the built-in fields,
// the markings and landmarks they generate, custom files, and every kind of bad file.
#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "soccer_vision/common/field_geometry.h"

using namespace soccer_vision;

namespace {

const std::string kFields = std::string(SOCCER_VISION_SOURCE_DIR) + "/config/fields/";

void expectSameField(const FieldGeometry& a, const FieldGeometry& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_DOUBLE_EQ(a.length, b.length);
  EXPECT_DOUBLE_EQ(a.width, b.width);
  EXPECT_DOUBLE_EQ(a.boundary, b.boundary);
  EXPECT_DOUBLE_EQ(a.line_width, b.line_width);
  EXPECT_DOUBLE_EQ(a.centre_radius, b.centre_radius);
  EXPECT_DOUBLE_EQ(a.penalty_area_depth, b.penalty_area_depth);
  EXPECT_DOUBLE_EQ(a.penalty_area_width, b.penalty_area_width);
  EXPECT_DOUBLE_EQ(a.goal_width, b.goal_width);
  EXPECT_DOUBLE_EQ(a.goal_depth, b.goal_depth);
  EXPECT_DOUBLE_EQ(a.goal_height, b.goal_height);
  EXPECT_DOUBLE_EQ(a.penalty_mark_distance, b.penalty_mark_distance);
  EXPECT_EQ(a.centre_line, b.centre_line);
  EXPECT_EQ(a.lines().size(), b.lines().size());
  EXPECT_EQ(a.landmarks().size(), b.landmarks().size());
}

std::string errorOf(const std::string& yaml) {
  try {
    parseFieldGeometry(yaml, "test.yaml");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(FieldGeometry, ConfigFilesEqualTheBuiltInFields) {
  expectSameField(loadFieldGeometry(kFields + "div_b.yaml"), FieldGeometry::divB());
  expectSameField(loadFieldGeometry(kFields + "div_a.yaml"), FieldGeometry::divA());
  expectSameField(fieldGeometryByName(""), FieldGeometry::divB());
  expectSameField(fieldGeometryByName("div_a"), FieldGeometry::divA());
  expectSameField(fieldGeometryByName(kFields + "div_a.yaml"), FieldGeometry::divA());
}

TEST(FieldGeometry, DivisionBMarkingsAndLandmarks) {
  const FieldGeometry f = FieldGeometry::divB();
  const auto lines = f.lines();
  ASSERT_EQ(lines.size(), 11u);  // 2 touch, 2 goal, halfway, 3 per penalty area
  std::set<std::string> names;
  for (const auto& l : lines) names.insert(l.name);
  EXPECT_EQ(names.size(), lines.size());
  EXPECT_TRUE(names.count("TopTouchLine") && names.count("LeftPenaltyStretch") &&
              names.count("RightFieldRightPenaltyStretch"));
  EXPECT_FALSE(names.count("CenterLine"));
  // The left penalty area's front line, 1 m in front of the goal line, 2 m wide.
  for (const auto& l : lines) {
    if (l.name != "LeftPenaltyStretch") continue;
    EXPECT_DOUBLE_EQ(l.a.x(), -3.5);
    EXPECT_DOUBLE_EQ(std::abs(l.b.y() - l.a.y()), 2.0);
  }
  ASSERT_EQ(f.circles().size(), 1u);
  EXPECT_TRUE(f.circles()[0].fullCircle());
  EXPECT_EQ(f.landmarks().size(), 17u);
  EXPECT_TRUE(f.onCarpet(4.75, 3.25));
  EXPECT_FALSE(f.onCarpet(4.85, 0));
  EXPECT_TRUE(f.inPlayingArea(4.5, -3.0));
  EXPECT_FALSE(f.inPlayingArea(4.6, 0));
}

TEST(FieldGeometry, DistancesToTheMarkingsAndTheCarpetEdge) {
  const FieldGeometry f = FieldGeometry::divB();
  EXPECT_NEAR(f.distanceToMarkings({-1.2, -2.96}), 0.04, 1e-12);  // the touch line
  EXPECT_NEAR(f.distanceToMarkings({-4.6, -3.1}), std::hypot(0.1, 0.1), 1e-12) << "beyond the corner";
  EXPECT_NEAR(f.distanceToMarkings({0.0, 0.52}), 0.0, 1e-12) << "the halfway line";
  EXPECT_NEAR(f.distanceToMarkings({0.3, 0.42}), std::hypot(0.3, 0.42) - 0.5, 1e-12) << "the centre circle";
  EXPECT_NEAR(f.distanceToMarkings({-4.0, 0.0}), 0.5, 1e-12) << "the penalty stretch, the goal line";
  EXPECT_NEAR(f.distanceToCarpetEdge({-4.75, 0.0}), 0.05, 1e-12);
  EXPECT_NEAR(f.distanceToCarpetEdge({0.0, 3.4}), 0.1, 1e-12) << "beyond it";
  EXPECT_NEAR(f.distanceToCarpetEdge({4.9, -3.4}), std::hypot(0.1, 0.1), 1e-12) << "beyond the corner";
  const LineSegment point{{1, 1}, {1, 1}, "point"};
  EXPECT_NEAR(point.distance({1, 2}), 1.0, 1e-12);
}

TEST(FieldGeometry, DivisionAIsTwelveByNineWithACentreLine) {
  const FieldGeometry f = FieldGeometry::divA();
  EXPECT_DOUBLE_EQ(f.halfLength(), 6.0);
  EXPECT_DOUBLE_EQ(f.halfWidth(), 4.5);
  bool centre_line = false;
  for (const auto& l : f.lines()) {
    if (l.name == "CenterLine") centre_line = (l.a - Eigen::Vector2d(-6, 0)).norm() < 1e-12;
    if (l.name == "RightPenaltyStretch") {
      EXPECT_DOUBLE_EQ(l.a.x(), 6.0 - 1.8);
    }
  }
  EXPECT_TRUE(centre_line);
  EXPECT_TRUE(f.onCarpet(6.2, 4.7));
  // Every landmark lies on a line or the centre circle.
  for (const auto& p : f.landmarks()) {
    double d = HUGE_VAL;
    for (const auto& l : f.lines()) {
      const Eigen::Vector2d ab = l.b - l.a;
      const double t = std::clamp((p.head<2>() - l.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (l.a + t * ab - p.head<2>()).norm());
    }
    for (const auto& c : f.circles()) d = std::min(d, c.distance(p.head<2>()));
    EXPECT_LT(d, 1e-9) << p.transpose();
  }
}

TEST(FieldGeometry, CustomFileReplacesTheMarkings) {
  const FieldGeometry f = parseFieldGeometry(R"(
name: lab
length: 4.0
width: 3.0
boundary: 0.25
lines:
  - {name: Bottom, p1: [-2, -1.5], p2: [2, -1.5]}
  - {name: Top, p1: [-2, 1.5], p2: [2, 1.5]}
  - {name: Halfway, p1: [0, -1.5], p2: [0, 1.5]}
arcs:
  - {name: Half circle, center: [0, 0], radius: 0.4, a1: -1.5707963267948966, a2: 1.5707963267948966}
)",
                                             "lab.yaml");
  EXPECT_EQ(f.name, "lab");
  ASSERT_EQ(f.lines().size(), 3u);
  const std::vector<CircleArc> arcs = f.circles();
  ASSERT_EQ(arcs.size(), 1u);
  const CircleArc& arc = arcs[0];
  EXPECT_FALSE(arc.fullCircle());
  EXPECT_NEAR(arc.distance({0.5, 0.0}), 0.1, 1e-12);                    // radially, inside the arc's range
  EXPECT_NEAR(arc.distance({-0.4, 0.0}), std::hypot(0.4, 0.4), 1e-12);  // nearest end point (0, +-0.4)
  const auto pts = arc.points(4);
  ASSERT_EQ(pts.size(), 5u);
  EXPECT_NEAR(pts.front().y(), -0.4, 1e-12);
  EXPECT_NEAR(pts[2].x(), 0.4, 1e-12);
  // End points (6, two shared by the halfway line) and crossings, once each.
  EXPECT_EQ(f.landmarks().size(), 6u);
  EXPECT_TRUE(f.onCarpet(2.2, 1.7));
  EXPECT_FALSE(f.onCarpet(2.3, 0));
}

TEST(FieldGeometry, BadFilesAreRefusedNamingTheKey) {
  EXPECT_NE(errorOf("lenght: 9").find("unknown key 'lenght'"), std::string::npos);
  EXPECT_NE(errorOf("length: 9\nlength: 12").find("given twice"), std::string::npos);
  EXPECT_NE(errorOf("length: .nan").find("'length'"), std::string::npos);
  EXPECT_NE(errorOf("width: -1").find("'width'"), std::string::npos);
  EXPECT_NE(errorOf("length: 1e9").find("'length'"), std::string::npos);
  EXPECT_NE(errorOf("length: nine").find("must be a number"), std::string::npos);
  EXPECT_NE(errorOf("penalty_area_depth: 5").find("penalty area"), std::string::npos);
  EXPECT_NE(errorOf("centre_line: maybe").find("centre_line"), std::string::npos);
  EXPECT_NE(errorOf("[1, 2]").find("top level"), std::string::npos);
  EXPECT_NE(errorOf("length: [").find("invalid YAML"), std::string::npos);
  EXPECT_NE(errorOf("lines: [{p1: [0, 0], p2: [0, 0]}]").find("zero-length"), std::string::npos);
  EXPECT_NE(errorOf("lines: [{p1: [0, 0]}]").find("p1 and p2"), std::string::npos);
  EXPECT_NE(errorOf("lines: [{p1: [0, 0], p2: [1, 0], colour: white}]").find("unknown key 'colour'"),
            std::string::npos);
  EXPECT_NE(errorOf("arcs: [{center: [0, 0], radius: 1, a1: 1, a2: 0}]").find("a1 < a2"), std::string::npos);
  EXPECT_NE(errorOf("arcs: [{center: [0, .inf], radius: 1}]").find("center"), std::string::npos);
  EXPECT_THROW(loadFieldGeometry(kFields + "no_such_field.yaml"), std::runtime_error);
  EXPECT_THROW(fieldGeometryByName("div_c"), std::runtime_error);
}
