#include <cmath>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "soccer_vision/ssl/geometry_packet.h"

using namespace soccer_vision;

namespace {

const SSL_FieldLineSegment* findLine(const SSL_GeometryFieldSize& f, const std::string& name) {
  for (const auto& l : f.field_lines()) {
    if (l.name() == name) return &l;
  }
  return nullptr;
}

// SSL-Vision's projection (its camera_calibration.cpp, field2image): rotate and translate into
// the camera, divide by depth, one radial coefficient, focal length and principal point.
Eigen::Vector2d sslVisionProject(const SSL_GeometryCameraCalibration& c, const Eigen::Vector3d& p_mm) {
  const Eigen::Quaterniond q(c.q3(), c.q0(), c.q1(), c.q2());  // Eigen: w first
  const Eigen::Vector3d p_c = q.normalized() * p_mm + Eigen::Vector3d(c.tx(), c.ty(), c.tz());
  const Eigen::Vector2d un(p_c.x() / p_c.z(), p_c.y() / p_c.z());
  const double ru = un.norm();
  const Eigen::Vector2d d = un * (1 + c.distortion() * ru * ru);
  return Eigen::Vector2d(c.principal_point_x(), c.principal_point_y()) + c.focal_length() * d;
}

}  // namespace

TEST(SslGeometryPacket, DivisionAFieldInWholeMillimetres) {
  const SSL_GeometryFieldSize f = ssl::fieldSize(FieldGeometry::divA());
  EXPECT_EQ(f.field_length(), 12000);
  EXPECT_EQ(f.field_width(), 9000);
  EXPECT_EQ(f.center_circle_radius(), 500);
  EXPECT_EQ(f.line_thickness(), 10);
  EXPECT_EQ(f.penalty_area_depth(), 1800);
  EXPECT_EQ(f.penalty_area_width(), 3600);
  EXPECT_FLOAT_EQ(f.ball_radius(), 21.5f);
  EXPECT_TRUE(f.IsInitialized());
}

TEST(SslGeometryPacket, LinesAndArcsCarryTheirShapeTypes) {
  const FieldGeometry field = FieldGeometry::divB();
  const SSL_GeometryFieldSize f = ssl::fieldSize(field);
  EXPECT_EQ(f.field_lines_size(), static_cast<int>(field.lines().size()));
  const SSL_FieldLineSegment* top = findLine(f, "TopTouchLine");
  ASSERT_NE(top, nullptr);
  EXPECT_EQ(top->type(), TopTouchLine);
  EXPECT_NEAR(top->p1().y(), 3000.0, 1e-3);  // y along the width, +y at the top
  EXPECT_NEAR(std::abs(top->p1().x() - top->p2().x()), 9000.0, 1e-3);
  const SSL_FieldLineSegment* stretch = findLine(f, "LeftFieldLeftPenaltyStretch");
  ASSERT_NE(stretch, nullptr);
  EXPECT_EQ(stretch->type(), LeftFieldLeftPenaltyStretch);
  ASSERT_EQ(f.field_arcs_size(), 1);
  EXPECT_EQ(f.field_arcs(0).type(), CenterCircle);
  EXPECT_NEAR(f.field_arcs(0).radius(), 500.0, 1e-3);
  EXPECT_NEAR(f.field_arcs(0).a2() - f.field_arcs(0).a1(), 2 * M_PI, 1e-5);
  EXPECT_EQ(ssl::shapeType("a custom line"), Undefined);
}

TEST(SslGeometryPacket, CameraCalibrationProjectsLikeOurCameraModel) {
  const FieldGeometry field = FieldGeometry::divB();
  const CameraModel camera = CameraModel::defaultCamera(field, 1);
  const SSL_GeometryCameraCalibration c = ssl::cameraCalibration(1, camera);
  EXPECT_EQ(c.camera_id(), 1u);
  EXPECT_EQ(c.pixel_image_width(), 1280u);
  EXPECT_NEAR(c.derived_camera_world_tz(), camera.cameraCentre().z() * 1000, 0.5);
  // Near the image centre, where our k2, k3 (not in the league's model) hardly matter, a field
  // point lands on the same pixel through the league's model as through ours.
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(2.25, 0.0, 0.0), Eigen::Vector3d(2.0, 0.5, 0.15), Eigen::Vector3d(2.6, -0.4, 0.0)}) {
    const auto ours = camera.project(p);
    ASSERT_TRUE(ours.has_value());
    const Eigen::Vector2d league = sslVisionProject(c, p * 1000);
    EXPECT_NEAR((league - *ours).norm(), 0.0, 0.5) << p.transpose();
  }
}

TEST(SslGeometryPacket, GeometryPacketHasTheFieldAndEveryCamera) {
  const FieldGeometry field = FieldGeometry::divB();
  const SSL_WrapperPacket p = ssl::geometryPacket(
      field, {{0, CameraModel::defaultCamera(field, 0)}, {1, CameraModel::defaultCamera(field, 1)}});
  ASSERT_TRUE(p.has_geometry());
  EXPECT_FALSE(p.has_detection());
  EXPECT_EQ(p.geometry().field().field_length(), 9000);
  ASSERT_EQ(p.geometry().calib_size(), 2);
  EXPECT_EQ(p.geometry().calib(1).camera_id(), 1u);
  EXPECT_TRUE(p.IsInitialized());
}
