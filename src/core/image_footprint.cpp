#include "soccer_vision/image_footprint.h"

#include <cmath>

namespace soccer_vision {

std::vector<Eigen::Vector3d> markerOutline(const MarkerShape& s, double x, double y, double theta, double z,
                                           int disc_points) {
  const double c = std::cos(theta), sn = std::sin(theta);
  auto world = [&](double lx, double ly) {
    return Eigen::Vector3d(x + c * lx - sn * ly, y + sn * lx + c * ly, z);
  };
  std::vector<Eigen::Vector3d> out;
  if (s.kind == MarkerShape::Kind::Disc) {
    for (int i = 0; i < disc_points; ++i) {
      const double a = 2 * M_PI * i / disc_points;
      out.push_back(world(s.x + s.radius * std::cos(a), s.y + s.radius * std::sin(a)));
    }
  } else {
    const double hx = s.size_x / 2, hy = s.size_y / 2;
    const double corners[5][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}, {-hx, -hy}};
    const int sub = std::max(1, disc_points / 4);
    for (int k = 0; k < 4; ++k) {
      for (int i = 0; i < sub; ++i) {
        const double t = static_cast<double>(i) / sub;
        out.push_back(world(s.x + corners[k][0] + t * (corners[k + 1][0] - corners[k][0]),
                            s.y + corners[k][1] + t * (corners[k + 1][1] - corners[k][1])));
      }
    }
  }
  return out;
}

double projectedArea(const CameraModel& camera, const std::vector<Eigen::Vector3d>& outline) {
  std::vector<Eigen::Vector2d> px;
  px.reserve(outline.size());
  for (const auto& p : outline) {
    const auto q = camera.project(p);
    if (!q) return 0;
    px.push_back(*q);
  }
  double twice = 0;
  for (std::size_t i = 0; i < px.size(); ++i) {
    const auto& a = px[i];
    const auto& b = px[(i + 1) % px.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return std::abs(twice) / 2;
}

double expectedMarkerArea(const CameraModel& camera, const MarkerShape& shape, double x, double y, double theta,
                          double z) {
  return projectedArea(camera, markerOutline(shape, x, y, theta, z));
}

double expectedBallArea(const CameraModel& camera, const Eigen::Vector3d& centre, double radius, int points) {
  const Eigen::Vector3d w = centre - camera.cameraCentre();
  const double d = w.norm();
  if (d <= radius) return 0;
  // Tangent points of the cone from the camera centre: a circle at distance d - r²/d
  // along w, radius r * sqrt(1 - r²/d²).
  const Eigen::Vector3d axis = w / d;
  const Eigen::Vector3d circle_centre = camera.cameraCentre() + axis * (d - radius * radius / d);
  const double circle_radius = radius * std::sqrt(1 - radius * radius / (d * d));
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  std::vector<Eigen::Vector3d> outline;
  for (int i = 0; i < points; ++i) {
    const double a = 2 * M_PI * i / points;
    outline.push_back(circle_centre + circle_radius * (std::cos(a) * u + std::sin(a) * v));
  }
  return projectedArea(camera, outline);
}

double shapeArea(const MarkerShape& s) {
  return s.kind == MarkerShape::Kind::Disc ? M_PI * s.radius * s.radius : s.size_x * s.size_y;
}

}  // namespace soccer_vision
