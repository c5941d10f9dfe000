#include "soccer_vision/plane_region.h"

#include <cmath>

#include <Eigen/Eigenvalues>

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

std::optional<PlaneRegion> projectToPlane(const Region& region, const CameraModel& camera, double plane_z) {
  const Eigen::Vector2d pixel(region.cx, region.cy);
  const auto centre = camera.pixelToField(pixel, plane_z);
  const auto j = pixelToPlaneJacobian(camera, pixel, plane_z);
  if (!centre || !j) return std::nullopt;
  PlaneRegion out;
  out.centre = centre->head<2>();
  Eigen::Matrix2d m;
  m << region.mu20, region.mu11, region.mu11, region.mu02;
  out.covariance = *j * m * j->transpose();
  out.area = region.area * std::abs(j->determinant());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(out.covariance);
  const Eigen::Vector2d minor = eig.eigenvectors().col(0);  // eigenvalues ascending
  out.minor_axis_angle = std::atan2(minor.y(), minor.x());
  const double lo = std::max(eig.eigenvalues()[0], 1e-18), hi = std::max(eig.eigenvalues()[1], 1e-18);
  out.elongation = std::sqrt(hi / lo);
  return out;
}

}  // namespace soccer_vision
