#include "soccer_vision/simulation/calibration_samples.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <opencv2/core.hpp>

#include "soccer_vision/common/ball.h"

namespace soccer_vision {
namespace {

constexpr int kPolygonVertices = 12;

// Point in the robot frame -> field point at the marker plane.
Eigen::Vector3d robotToField(const RobotState& r, double x, double y, double z) {
  const double c = std::cos(r.theta), s = std::sin(r.theta);
  return {r.x + c * x - s * y, r.y + s * x + c * y, z};
}

// Outline of a marker shape (robot frame), scaled about its centre by `shrink`.
std::vector<Eigen::Vector2d> outline(const MarkerShape& m, double shrink) {
  std::vector<Eigen::Vector2d> pts;
  if (m.kind == MarkerShape::Kind::Disc) {
    for (int i = 0; i < kPolygonVertices; ++i) {
      const double a = 2 * M_PI * i / kPolygonVertices;
      pts.emplace_back(m.x + shrink * m.radius * std::cos(a), m.y + shrink * m.radius * std::sin(a));
    }
  } else {
    const double hx = shrink * m.size_x / 2, hy = shrink * m.size_y / 2;
    pts = {{m.x - hx, m.y - hy}, {m.x + hx, m.y - hy}, {m.x + hx, m.y + hy}, {m.x - hx, m.y + hy}};
  }
  return pts;
}

// The shape grown (negative: shrunk) by `by` metres on every side; nullopt when nothing is left.
std::optional<MarkerShape> inset(MarkerShape m, double by) {
  if (m.kind == MarkerShape::Kind::Disc) {
    m.radius -= by;
    if (m.radius <= 0) return std::nullopt;
  } else {
    m.size_x -= 2 * by;
    m.size_y -= 2 * by;
    if (m.size_x <= 0 || m.size_y <= 0) return std::nullopt;
  }
  return m;
}

// Metres per pixel at a field point, as the camera sees a small horizontal step there.
double metresPerPixel(const CameraModel& camera, const Eigen::Vector3d& p) {
  constexpr double kStep = 0.01;
  const auto a = camera.project(p), b = camera.project(p + Eigen::Vector3d(kStep, 0, 0)),
             c = camera.project(p + Eigen::Vector3d(0, kStep, 0));
  if (!a || !b || !c) return 0;
  return kStep / std::min((*b - *a).norm(), (*c - *a).norm());
}

// Distance from a point (robot frame) to the nearest marker edge, negative inside.
double markerDistance(const MarkerShape& m, double x, double y) {
  if (m.kind == MarkerShape::Kind::Disc) return std::hypot(x - m.x, y - m.y) - m.radius;
  const double dx = std::abs(x - m.x) - m.size_x / 2, dy = std::abs(y - m.y) - m.size_y / 2;
  return std::hypot(std::max(dx, 0.0), std::max(dy, 0.0)) + std::min(std::max(dx, dy), 0.0);
}

// The spot of the robot top farthest from every marker and from the rim.
Eigen::Vector2d clearestTopSpot(const std::vector<ColoredMarker>& markers, double radius, double& clearance) {
  clearance = -1;
  Eigen::Vector2d best(0, 0);
  for (double x = -radius; x <= radius; x += 0.0025) {
    for (double y = -radius; y <= radius; y += 0.0025) {
      double c = radius - std::hypot(x, y);
      for (const auto& m : markers) c = std::min(c, markerDistance(m.shape, x, y));
      if (c > clearance) {
        clearance = c;
        best = {x, y};
      }
    }
  }
  return best;
}

class PolygonProjector {
 public:
  PolygonProjector(const CameraModel& camera, double margin) : camera_(camera), margin_(margin) {}
  // Projects field points; false if any falls outside the image margin.
  bool project(const std::vector<Eigen::Vector3d>& field_pts, Polygon& out) const {
    out.clear();
    for (const auto& p : field_pts) {
      const auto px = camera_.project(p);
      if (!px || !camera_.inImage(*px, margin_)) return false;
      out.push_back(*px);
    }
    return true;
  }

 private:
  const CameraModel& camera_;
  double margin_;
};

std::vector<Eigen::Vector3d> square(double cx, double cy, double half, double z) {
  return {{cx - half, cy - half, z},
          {cx + half, cy - half, z},
          {cx + half, cy + half, z},
          {cx - half, cy + half, z}};
}

}  // namespace

ColorSamples calibrationSamples(const SceneState& scene, const CameraModel& camera,
                                const FieldGeometry& field, const PatternSet& patterns,
                                const SampleOptions& options) {
  ColorSamples samples;
  const PolygonProjector projector(camera, options.image_margin), to_border(camera, 0.0);
  Polygon poly;

  for (const auto& r : scene.robots) {
    const double z_top = patterns.height(r.team);
    const auto markers = patterns.markers(r.team, r.id);
    const bool in_view = options.robots_in_view_to_border &&
                         camera.allInImage(markerOutlinePoints(patterns, r.team, r.id, r.x, r.y, r.theta));
    const PolygonProjector& marker_projector = in_view ? to_border : projector;
    for (const auto& m : markers) {
      std::vector<Eigen::Vector3d> pts;
      MarkerShape shape = m.shape;
      double scale = options.shrink;
      if (options.inset_px > 0) {
        const double mpp = metresPerPixel(camera, robotToField(r, m.shape.x, m.shape.y, z_top));
        if (mpp <= 0) continue;
        const auto inner = inset(m.shape, options.inset_px * mpp);
        const auto half_width = [](const MarkerShape& s) {
          return s.kind == MarkerShape::Kind::Disc ? s.radius : std::min(s.size_x, s.size_y) / 2;
        };
        if (inner && half_width(*inner) >= 0.5 * mpp) {
          shape = *inner;
        } else {
          // Thinner than twice the inset: a user paints a 1 px stroke along its middle (or
          // clicks the centre of a dot); under 2 px across, not even that.
          if (half_width(m.shape) < mpp) continue;
          if (shape.kind == MarkerShape::Kind::Disc) {
            shape.radius = 0.6 * mpp;
          } else {
            double& minor = shape.size_x < shape.size_y ? shape.size_x : shape.size_y;
            double& major = shape.size_x < shape.size_y ? shape.size_y : shape.size_x;
            minor = mpp;
            major = std::max(major - 2 * options.inset_px * mpp, mpp);
          }
        }
        scale = 1.0;
      }
      for (const auto& q : outline(shape, scale)) pts.push_back(robotToField(r, q.x(), q.y(), z_top));
      if (marker_projector.project(pts, poly)) samples[m.color].push_back(poly);
    }
    double clearance = 0;
    const Eigen::Vector2d spot = clearestTopSpot(markers, patterns.robot_radius, clearance);
    if (clearance > 0.006) {
      MarkerShape s;
      s.x = spot.x();
      s.y = spot.y();
      s.radius = clearance;
      std::vector<Eigen::Vector3d> pts;
      for (const auto& q : outline(s, options.shrink)) pts.push_back(robotToField(r, q.x(), q.y(), z_top));
      if (projector.project(pts, poly)) samples[ColorClass::RobotTop].push_back(poly);
    }
  }

  for (const auto& b : scene.balls) {
    // A disc on the plane through the ball centre: its outline projects inside the ball.
    double radius = options.shrink * kBallRadius;
    if (options.inset_px > 0) {
      const double mpp = metresPerPixel(camera, Eigen::Vector3d(b.x, b.y, b.z));
      radius = kBallRadius - options.inset_px * mpp;
      if (mpp <= 0 || kBallRadius < mpp) continue;  // under 2 px across
      if (radius < 0.5 * mpp) radius = 0.6 * mpp;   // a click on its centre pixel, as for a dot
    }
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < kPolygonVertices; ++i) {
      const double a = 2 * M_PI * i / kPolygonVertices;
      pts.emplace_back(b.x + radius * std::cos(a), b.y + radius * std::sin(a), b.z);
    }
    if (projector.project(pts, poly)) samples[ColorClass::Orange].push_back(poly);
  }

  // Carpet: 10 cm squares on a coarse grid, away from lines, robots and balls.
  const double keep_out = 0.25, half = 0.05;
  int carpet = 0;
  for (double x = -field.halfLength() + 0.4; x < field.halfLength() && carpet < options.carpet_patches;
       x += 0.83) {
    for (double y = -field.halfWidth() + 0.4; y < field.halfWidth() && carpet < options.carpet_patches;
         y += 0.97) {
      bool clear = field.distanceToMarkings({x, y}) > half + 0.05;
      for (const auto& r : scene.robots) clear = clear && std::hypot(r.x - x, r.y - y) > keep_out;
      for (const auto& b : scene.balls) clear = clear && std::hypot(b.x - x, b.y - y) > keep_out;
      if (clear && projector.project(square(x, y, half, 0.0), poly)) {
        samples[ColorClass::Carpet].push_back(poly);
        ++carpet;
      }
    }
  }

  // Lines: thin strips along the middle of each straight line, 30 cm long, clear of robots.
  for (const auto& s : field.lines()) {
    const Eigen::Vector2d mid = (s.a + s.b) / 2, dir = (s.b - s.a).normalized();
    const Eigen::Vector2d n(-dir.y(), dir.x());
    bool clear = true;
    for (const auto& r : scene.robots) clear = clear && (Eigen::Vector2d(r.x, r.y) - mid).norm() > 0.4;
    const double hl = 0.15, hw = 0.25 * field.line_width;
    std::vector<Eigen::Vector3d> pts;
    for (const Eigen::Vector2d& c :
         {Eigen::Vector2d(mid - hl * dir - hw * n), Eigen::Vector2d(mid + hl * dir - hw * n),
          Eigen::Vector2d(mid + hl * dir + hw * n), Eigen::Vector2d(mid - hl * dir + hw * n)}) {
      pts.emplace_back(c.x(), c.y(), 0.0);
    }
    if (clear && projector.project(pts, poly)) samples[ColorClass::Line].push_back(poly);
  }
  return samples;
}

std::vector<FieldCorrespondence> fieldCorrespondences(const CameraModel& camera, const FieldGeometry& field,
                                                      double image_margin) {
  std::vector<FieldCorrespondence> out;
  for (const auto& p : field.landmarks()) {
    const auto px = camera.project(p);
    if (px && camera.inImage(*px, image_margin)) out.push_back({*px, p});
  }
  return out;
}

void addClickNoise(std::vector<FieldCorrespondence>& points, double sigma_px, std::uint64_t seed) {
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ULL + 0x632BE59BD9B4E019ULL);
  for (FieldCorrespondence& p : points)
    p.pixel += Eigen::Vector2d(rng.gaussian(sigma_px), rng.gaussian(sigma_px));
}

}  // namespace soccer_vision
