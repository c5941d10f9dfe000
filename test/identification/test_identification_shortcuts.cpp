// The shortcuts identification takes for speed give what the general functions give:
// expectedMarkerArea (outline walked, not stored) against projectedArea of markerOutline,
// projectCentroidToPlane against projectToPlane's centre, CameraModel::project (inverse pose
// kept) against the pose inverted per call. Equality is exact: identification's results
// must not move by a bit.
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/identification/image_footprint.h"
#include "soccer_vision/identification/plane_region.h"

using namespace soccer_vision;

namespace {

// The built-in camera, and one tilted with stronger, decentred distortion.
std::vector<CameraModel> cameras() {
  const FieldGeometry field;
  CameraModel tilted_base = CameraModel::defaultCamera(field, 1);
  CameraIntrinsics k = tilted_base.intrinsics();
  k.dist = {-0.28, 0.09, 0.002, -0.001, -0.01};
  Eigen::Isometry3d pose = tilted_base.fieldTCamera();
  pose.linear() = pose.linear() * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return {CameraModel::defaultCamera(field, 0), CameraModel(k, pose)};
}

std::vector<MarkerShape> shapes() {
  std::vector<MarkerShape> out{PatternSet::twoTag().team_marker};
  for (const PatternSet& p : {PatternSet::twoTag(), PatternSet::ssl()}) {
    out.push_back(p.team_marker);
    out.insert(out.end(), p.slots.begin(), p.slots.end());
  }
  return out;
}

}  // namespace

TEST(FootprintShortcuts, ExpectedMarkerAreaIsTheProjectedOutlineArea) {
  int compared = 0;
  for (const CameraModel& camera : cameras()) {
    for (const MarkerShape& shape : shapes()) {
      for (double x = -4.4; x <= 0.4; x += 0.37) {
        for (double y = -3.2; y <= 3.2; y += 0.41) {
          const double theta = 0.7 * x + 1.3 * y;
          const double area = expectedMarkerArea(camera, shape, x, y, theta, 0.15);
          EXPECT_EQ(area, projectedArea(camera, markerOutline(shape, x, y, theta, 0.15)));
          if (area > 0) ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 2000);
  // A 40 mm disc at the image centre of the 4 m camera (about 5 mm per pixel): ~50 px.
  const MarkerShape disc = PatternSet::ssl().slots.front();
  const CameraModel camera = cameras().front();
  const Eigen::Vector3d c = camera.pixelToField({639.5, 511.5}, 0.15).value();
  const double at_centre = expectedMarkerArea(camera, disc, c.x() - disc.x, c.y() - disc.y, 0, 0.15);
  EXPECT_NEAR(at_centre, M_PI * 20 * 20 / (5.0 * 5.0), 15);
}

TEST(FootprintShortcuts, ExpectedMarkerAreaIsZeroBehindTheCamera) {
  const CameraModel camera = cameras().front();
  const MarkerShape disc = PatternSet::ssl().team_marker;
  const double above = camera.cameraCentre().z() + 0.5;
  EXPECT_EQ(expectedMarkerArea(camera, disc, camera.cameraCentre().x(), camera.cameraCentre().y(), 0, above),
            0.0);
}

TEST(FootprintShortcuts, CentroidProjectionIsProjectToPlanesCentre) {
  int compared = 0;
  for (const CameraModel& camera : cameras()) {
    for (double u = 3; u < camera.width(); u += 57.3) {
      for (double v = 2; v < camera.height(); v += 61.7) {
        Region r;
        r.cx = u;
        r.cy = v;
        r.area = 40;
        r.mu20 = 3.1;
        r.mu02 = 2.7;
        r.mu11 = 0.4;
        const auto full = projectToPlane(r, camera, 0.15);
        const auto centre = projectCentroidToPlane(r, camera, 0.15);
        ASSERT_EQ(full.has_value(), centre.has_value()) << u << ", " << v;
        if (!full) continue;
        EXPECT_EQ(full->centre, *centre);
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 400);
}

TEST(FootprintShortcuts, CentroidProjectionRejectsWhatProjectToPlaneRejects) {
  const CameraModel camera = cameras().front();
  Region good;
  good.cx = 600;
  good.cy = 500;
  good.area = 30;
  good.mu20 = good.mu02 = 2;
  ASSERT_TRUE(projectCentroidToPlane(good, camera, 0.15));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < 6; ++k) {
    Region bad = good;
    if (k == 0) bad.cx = nan;
    if (k == 1) bad.cy = std::numeric_limits<double>::infinity();
    if (k == 2) bad.mu20 = nan;
    if (k == 3) bad.mu11 = nan;
    if (k == 4) bad.mu02 = nan;
    if (k == 5) bad.area = 0;
    EXPECT_FALSE(projectToPlane(bad, camera, 0.15)) << k;
    EXPECT_FALSE(projectCentroidToPlane(bad, camera, 0.15)) << k;
  }
  // A plane above the camera: no ray going down meets it.
  EXPECT_FALSE(projectCentroidToPlane(good, camera, camera.cameraCentre().z() + 1));
}

TEST(FootprintShortcuts, ProjectEqualsThePoseInvertedPerCall) {
  for (const CameraModel& camera : cameras()) {
    const Eigen::Isometry3d camera_T_field = camera.fieldTCamera().inverse();
    const CameraIntrinsics& k = camera.intrinsics();
    for (double x = -4.7; x <= 0.5; x += 0.53) {
      for (double y = -3.3; y <= 3.3; y += 0.47) {
        const Eigen::Vector3d p(x, y, 0.15);
        const Eigen::Vector3d pc = camera_T_field * p;
        const Eigen::Vector2d xy = camera.distortNormalized({pc.x() / pc.z(), pc.y() / pc.z()});
        const auto px = camera.project(p);
        ASSERT_TRUE(px);
        EXPECT_EQ(*px, Eigen::Vector2d(k.fx * xy.x() + k.cx, k.fy * xy.y() + k.cy));
      }
    }
  }
}
