// Test helper: the Region a perfect segmentation would produce for a marker or the ball,
// by rasterising the shape through the camera model with sub-pixel coverage (8 x 8
// samples per pixel, each ray intersected with the marker plane / the ball sphere).
#pragma once

#include <cmath>
#include <functional>

#include <opencv2/core.hpp>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision::test {

// Coverage-weighted moments of the pixels for which inside(sample pixel) holds, searched
// in a box of +-reach px around `centre`.
inline Region rasterise(ColorClass color, const Eigen::Vector2d& centre, int reach,
                        const std::function<bool(const Eigen::Vector2d&)>& inside) {
  double w = 0, su = 0, sv = 0, suu = 0, suv = 0, svv = 0;
  int umin = 1 << 30, vmin = 1 << 30, umax = -1, vmax = -1;
  const int n = 8;
  for (int v = static_cast<int>(std::lround(centre.y())) - reach; v <= std::lround(centre.y()) + reach; ++v) {
    for (int u = static_cast<int>(std::lround(centre.x())) - reach; u <= std::lround(centre.x()) + reach;
         ++u) {
      int hits = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) hits += inside({u - 0.5 + (i + 0.5) / n, v - 0.5 + (j + 0.5) / n});
      if (!hits) continue;
      const double a = static_cast<double>(hits) / (n * n);
      w += a;
      su += a * u;
      sv += a * v;
      suu += a * u * u;
      suv += a * u * v;
      svv += a * v * v;
      umin = std::min(umin, u);
      vmin = std::min(vmin, v);
      umax = std::max(umax, u);
      vmax = std::max(vmax, v);
    }
  }
  Region r;
  r.color = color;
  if (w <= 0) return r;
  r.area = static_cast<std::uint32_t>(std::lround(w));
  r.cx = su / w;
  r.cy = sv / w;
  r.mu20 = suu / w - r.cx * r.cx;
  r.mu11 = suv / w - r.cx * r.cy;
  r.mu02 = svv / w - r.cy * r.cy;
  r.orientation = 0.5 * std::atan2(2 * r.mu11, r.mu20 - r.mu02);
  r.bbox = cv::Rect(umin, vmin, umax - umin + 1, vmax - vmin + 1);
  return r;
}

// Pixels inside the image: markerRegion's `keep` for a marker the image's edge cuts.
inline std::function<bool(const Eigen::Vector2d&)> inImage(const CameraModel& camera) {
  return [w = camera.width(), h = camera.height()](const Eigen::Vector2d& p) {
    return p.x() >= -0.5 && p.y() >= -0.5 && p.x() < w - 0.5 && p.y() < h - 0.5;
  };
}

// Region of one marker (shape in the robot frame) of a robot at (x, y, theta), plane z;
// with `keep`, only its (sub-)pixels for which keep holds (a part the image's edge left).
inline Region markerRegion(const CameraModel& camera, const MarkerShape& s, ColorClass color, double x,
                           double y, double theta, double z,
                           const std::function<bool(const Eigen::Vector2d&)>& keep = {}) {
  const double c = std::cos(theta), sn = std::sin(theta);
  const Eigen::Vector3d centre(x + c * s.x - sn * s.y, y + sn * s.x + c * s.y, z);
  const auto px = camera.project(centre);
  return rasterise(color, *px, 14, [&](const Eigen::Vector2d& p) {
    if (keep && !keep(p)) return false;
    const auto f = camera.pixelToField(p, z);
    if (!f) return false;
    const double dx = f->x() - x, dy = f->y() - y;
    const double lx = c * dx + sn * dy - s.x, ly = -sn * dx + c * dy - s.y;
    if (s.kind == MarkerShape::Kind::Disc) return lx * lx + ly * ly <= s.radius * s.radius;
    return std::abs(lx) <= s.size_x / 2 && std::abs(ly) <= s.size_y / 2;
  });
}

// Region of a ball (sphere of `radius` centred at `centre`).
inline Region ballRegion(const CameraModel& camera, const Eigen::Vector3d& centre,
                         double radius = kBallRadius) {
  const auto px = camera.project(centre);
  return rasterise(ColorClass::Orange, *px, 10, [&](const Eigen::Vector2d& p) {
    const Eigen::Vector3d ray = camera.pixelRay(p);
    const Eigen::Vector3d w = centre - camera.cameraCentre();
    return (w - w.dot(ray) * ray).norm() <= radius;
  });
}

// A disc-shaped blob of the given colour of `radius_m` on plane z at (x, y): stray paint.
inline Region discBlob(const CameraModel& camera, ColorClass color, double x, double y, double radius_m,
                       double z) {
  MarkerShape s;
  s.radius = radius_m;
  return markerRegion(camera, s, color, x, y, 0, z);
}

}  // namespace soccer_vision::test
