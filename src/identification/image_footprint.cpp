#include "soccer_vision/identification/image_footprint.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace soccer_vision {

namespace {

// Calls visit(point) for each outline vertex of markerOutline's, in order; the area code
// walks the outline without storing it (it runs for every marker of every hypothesis).
template <typename Visit>
void visitMarkerOutline(const MarkerShape& s, double x, double y, double theta, double z, int disc_points,
                        Visit&& visit) {
  const double c = std::cos(theta), sn = std::sin(theta);
  auto world = [&](double lx, double ly) {
    return Eigen::Vector3d(x + c * lx - sn * ly, y + sn * lx + c * ly, z);
  };
  if (s.kind == MarkerShape::Kind::Disc) {
    // The default disc's vertex directions, computed once (the same values as below).
    static const auto unit16 = [] {
      std::array<std::array<double, 2>, 16> u{};
      for (int i = 0; i < 16; ++i) {
        const double a = 2 * M_PI * i / 16;
        u[i] = {std::cos(a), std::sin(a)};
      }
      return u;
    }();
    for (int i = 0; i < disc_points; ++i) {
      if (disc_points == 16) {
        visit(world(s.x + s.radius * unit16[i][0], s.y + s.radius * unit16[i][1]));
        continue;
      }
      const double a = 2 * M_PI * i / disc_points;
      visit(world(s.x + s.radius * std::cos(a), s.y + s.radius * std::sin(a)));
    }
  } else {
    const double hx = s.size_x / 2, hy = s.size_y / 2;
    const double corners[5][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}, {-hx, -hy}};
    const int sub = std::max(1, disc_points / 4);
    for (int k = 0; k < 4; ++k) {
      for (int i = 0; i < sub; ++i) {
        const double t = static_cast<double>(i) / sub;
        visit(world(s.x + corners[k][0] + t * (corners[k + 1][0] - corners[k][0]),
                    s.y + corners[k][1] + t * (corners[k + 1][1] - corners[k][1])));
      }
    }
  }
}

// Shoelace sum over projected vertices fed one at a time (closing edge in finish()).
class ProjectedAreaAccumulator {
 public:
  explicit ProjectedAreaAccumulator(const CameraModel& camera) : camera_(camera) {}
  void add(const Eigen::Vector3d& p) {
    if (behind_) return;
    const auto q = camera_.project(p);
    if (!q) {
      behind_ = true;
      return;
    }
    if (count_ == 0) {
      first_ = *q;
    } else {
      twice_ += last_.x() * q->y() - q->x() * last_.y();
    }
    last_ = *q;
    ++count_;
  }
  double finish() const {
    if (behind_ || count_ == 0) return 0;
    const double twice = twice_ + (last_.x() * first_.y() - first_.x() * last_.y());
    return std::abs(twice) / 2;
  }

 private:
  const CameraModel& camera_;
  Eigen::Vector2d first_{0, 0}, last_{0, 0};
  double twice_ = 0;
  int count_ = 0;
  bool behind_ = false;
};

}  // namespace

std::vector<Eigen::Vector3d> markerOutline(const MarkerShape& s, double x, double y, double theta, double z,
                                           int disc_points) {
  std::vector<Eigen::Vector3d> out;
  visitMarkerOutline(s, x, y, theta, z, disc_points, [&](const Eigen::Vector3d& p) { out.push_back(p); });
  return out;
}

double projectedArea(const CameraModel& camera, const std::vector<Eigen::Vector3d>& outline) {
  ProjectedAreaAccumulator area(camera);
  for (const auto& p : outline) area.add(p);
  return area.finish();
}

double expectedMarkerArea(const CameraModel& camera, const MarkerShape& shape, double x, double y,
                          double theta, double z) {
  ProjectedAreaAccumulator area(camera);
  visitMarkerOutline(shape, x, y, theta, z, 16, [&](const Eigen::Vector3d& p) { area.add(p); });
  return area.finish();
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
