#include <gtest/gtest.h>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"

using namespace soccer_vision;

TEST(CameraModel, DistortionRoundTripOverTheWholeImage) {
  const auto cam = CameraModel::defaultCamera(FieldGeometry{}, 0);
  double worst = 0;
  for (double u = 0; u < cam.width(); u += 37) {
    for (double v = 0; v < cam.height(); v += 41) {
      const Eigen::Vector3d ray = cam.pixelRay({u, v});
      const auto back = cam.project(cam.cameraCentre() + 3.0 * ray);
      ASSERT_TRUE(back);
      worst = std::max(worst, (*back - Eigen::Vector2d(u, v)).norm());
    }
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(CameraModel, PixelToFieldRoundTripAtMarkerAndBallHeights) {
  const auto cam = CameraModel::defaultCamera(FieldGeometry{}, 1);
  for (double z : {0.0, 0.0215, 0.15}) {
    for (double x : {0.0, 1.3, 2.25, 4.5}) {
      for (double y : {-3.0, -0.7, 0.0, 2.9}) {
        const auto px = cam.project({x, y, z});
        ASSERT_TRUE(px);
        const auto p = cam.pixelToField(*px, z);
        ASSERT_TRUE(p);
        EXPECT_NEAR(p->x(), x, 1e-9);
        EXPECT_NEAR(p->y(), y, 1e-9);
        EXPECT_NEAR(p->z(), z, 1e-12);
      }
    }
  }
}

TEST(CameraModel, DefaultCamerasCoverTheirHalfWithOverlapAndBoundary) {
  const FieldGeometry field;
  const auto cam0 = CameraModel::defaultCamera(field, 0);
  const auto cam1 = CameraModel::defaultCamera(field, 1);
  const double hl = field.halfLength() + field.boundary, hw = field.halfWidth() + field.boundary;
  // Camera 0: x in [-4.8, 0.3], camera 1: x in [-0.3, 4.8], both y in [-3.3, 3.3].
  for (double y : {-hw, 0.0, hw}) {
    for (double x : {-hl, -2.0, 0.3}) EXPECT_TRUE(cam0.inImage(*cam0.project({x, y, 0.0}))) << x << " " << y;
    for (double x : {-0.3, 2.0, hl}) EXPECT_TRUE(cam1.inImage(*cam1.project({x, y, 0.0}))) << x << " " << y;
  }
  // Roughly 4 m above the carpet, about 5 mm per pixel at the image centre.
  EXPECT_NEAR(cam0.cameraCentre().z(), 4.0, 0.05);
  const auto a = cam0.pixelToField({640, 512}, 0.0), b = cam0.pixelToField({641, 512}, 0.0);
  EXPECT_NEAR((*a - *b).norm(), 0.005, 0.0005);
}

TEST(CameraModel, ProjectInImageGivesThePixelOnlyInsideTheImageAndItsMargin) {
  const auto cam = CameraModel::defaultCamera(FieldGeometry{}, 0);
  // A field point projected 1 px beyond the left edge (u = -1.5): out of the image, in it
  // with a margin of -2 px (reaching beyond the edge), and the same pixel as project().
  const Eigen::Vector3d beyond = *cam.pixelToField({-1.5, 512.0}, 0.0);
  EXPECT_FALSE(cam.projectInImage(beyond));
  const auto reached = cam.projectInImage(beyond, -2.0);
  ASSERT_TRUE(reached);
  EXPECT_NEAR((*reached - *cam.project(beyond)).norm(), 0.0, 1e-12);
  // Inside, but nearer the edge than a 3 px margin.
  const Eigen::Vector3d near_edge = *cam.pixelToField({1.0, 512.0}, 0.0);
  EXPECT_TRUE(cam.projectInImage(near_edge));
  EXPECT_FALSE(cam.projectInImage(near_edge, 3.0));
  // Behind the camera: no pixel at all.
  EXPECT_FALSE(cam.projectInImage(cam.cameraCentre() + Eigen::Vector3d(0, 0, 1.0), -1e6));
  // All points in the image, or not all.
  EXPECT_TRUE(cam.allInImage({near_edge, *cam.pixelToField({640.0, 512.0}, 0.0)}));
  EXPECT_FALSE(cam.allInImage({near_edge, beyond}));
  EXPECT_TRUE(cam.allInImage({}));
}

TEST(CameraModel, ScaledCameraSeesTheSameFieldPoint) {
  const auto cam = CameraModel::defaultCamera(FieldGeometry{}, 0);
  const auto half = cam.scaled(640, 512);
  const Eigen::Vector3d p(-1.7, 0.9, 0.15);
  const auto full = *cam.project(p), small = *half.project(p);
  EXPECT_NEAR((full.x() + 0.5) / 2 - 0.5, small.x(), 1e-9);
  EXPECT_NEAR((full.y() + 0.5) / 2 - 0.5, small.y(), 1e-9);
}

TEST(CameraModel, PointsBehindTheCameraDoNotProject) {
  const auto cam = CameraModel::defaultCamera(FieldGeometry{}, 0);
  EXPECT_FALSE(cam.project({-2.25, 0.0, 5.0}));
  EXPECT_FALSE(cam.pixelToField({640, 512}, 4.5));  // plane above the camera
}
