#include "soccer_vision/identification/plane_region.h"

#include <cmath>

#include "soccer_vision/segmentation/region_moments.h"

namespace soccer_vision {

std::optional<Eigen::Matrix2d> pixelToPlaneJacobian(const CameraModel& camera, const Eigen::Vector2d& pixel,
                                                    double plane_z) {
  const double h = 0.5;
  const auto xp = camera.pixelToField(pixel + Eigen::Vector2d(h, 0), plane_z);
  const auto xm = camera.pixelToField(pixel - Eigen::Vector2d(h, 0), plane_z);
  const auto yp = camera.pixelToField(pixel + Eigen::Vector2d(0, h), plane_z);
  const auto ym = camera.pixelToField(pixel - Eigen::Vector2d(0, h), plane_z);
  if (!xp || !xm || !yp || !ym) return std::nullopt;
  Eigen::Matrix2d j;
  j.col(0) = (*xp - *xm).head<2>() / (2 * h);
  j.col(1) = (*yp - *ym).head<2>() / (2 * h);
  return j;
}

namespace {

// Corrupt input (a bad message) must not turn into NaN poses downstream.
bool usableRegion(const Region& region) {
  return std::isfinite(region.cx) && std::isfinite(region.cy) && std::isfinite(region.mu20) &&
         std::isfinite(region.mu11) && std::isfinite(region.mu02) && region.area != 0;
}

}  // namespace

std::optional<Eigen::Vector2d> projectCentroidToPlane(const Region& region, const CameraModel& camera,
                                                      double plane_z) {
  if (!usableRegion(region)) return std::nullopt;
  const auto centre = camera.pixelToField(Eigen::Vector2d(region.cx, region.cy), plane_z);
  if (!centre || !centre->allFinite()) return std::nullopt;
  return Eigen::Vector2d(centre->head<2>());
}

std::optional<PlaneRegion> projectToPlane(const Region& region, const CameraModel& camera, double plane_z) {
  if (!usableRegion(region)) return std::nullopt;
  const Eigen::Vector2d pixel(region.cx, region.cy);
  const auto centre = camera.pixelToField(pixel, plane_z);
  const auto j = pixelToPlaneJacobian(camera, pixel, plane_z);
  if (!centre || !j || !centre->allFinite() || !j->allFinite()) return std::nullopt;
  PlaneRegion out;
  out.centre = centre->head<2>();
  Eigen::Matrix2d m;
  m << region.mu20, region.mu11, region.mu11, region.mu02;
  out.covariance = *j * m * j->transpose();
  out.area = region.area * std::abs(j->determinant());
  const double a = out.covariance(0, 0), b = out.covariance(0, 1), c = out.covariance(1, 1);
  out.minor_axis_angle = majorAxisAngle(a, b, c) + M_PI / 2;
  const PrincipalDeviations sd = principalDeviations(a, b, c);
  out.elongation = sd.major > 0 ? sd.elongation() : 1.0;  // a point has no axis
  return out;
}

}  // namespace soccer_vision
