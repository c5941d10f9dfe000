// A segmentation region seen on a horizontal field plane (marker tops at 150 mm, ball
// centres at 21.5 mm): its centroid through CameraModel::pixelToField, and its second
// moments and area carried through the local Jacobian of the pixel -> plane mapping, so
// that shape (the team tag's axes) and size are judged in metres, free of perspective
// and lens distortion to first order.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

struct PlaneRegion {
  Eigen::Vector2d centre{0, 0};                          // m, on the plane
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // m², central second moments
  double area = 0;                                       // m², pixel area x |det J|
  // Minor axis of the moment ellipse (rad, modulo pi) and sqrt(major / minor eigenvalue):
  // 1 for a disc, size_y / size_x for a rectangle.
  double minor_axis_angle = 0;
  double elongation = 1;
};

// d(plane x, y) / d(pixel u, v) at a raw pixel (central differences of pixelToField over
// +-0.5 px); nullopt where the rays miss the plane.
std::optional<Eigen::Matrix2d> pixelToPlaneJacobian(const CameraModel& camera, const Eigen::Vector2d& pixel,
                                                    double plane_z);

// nullopt where the centroid's ray misses the plane, or for a region with a zero area or
// non-finite centroid / moments.
std::optional<PlaneRegion> projectToPlane(const Region& region, const CameraModel& camera, double plane_z);

// Only the centroid (PlaneRegion::centre, one undistortion instead of five): nullopt for
// the same input and centroid rays as projectToPlane. Where projectToPlane also needs the
// rays 0.5 px around the centroid to hit the plane, this does not.
std::optional<Eigen::Vector2d> projectCentroidToPlane(const Region& region, const CameraModel& camera,
                                                      double plane_z);

}  // namespace soccer_vision
