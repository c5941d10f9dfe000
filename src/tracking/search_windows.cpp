#include "soccer_vision/tracking/search_windows.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace soccer_vision {
namespace {

// Largest standard deviation of a 2x2 position covariance [m].
double largestSigma(const Eigen::Matrix2d& P) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(P);
  return std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()));
}

// Pixels spanned by a field distance `metres` around `p` (worst direction of x, y).
double pixelsFor(const CameraModel& camera, const Eigen::Vector3d& p, const Eigen::Vector2d& centre,
                 double metres) {
  if (metres <= 0) return 0;
  double pixels = 0;
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(metres, 0, 0), Eigen::Vector3d(-metres, 0, 0),
                                        Eigen::Vector3d(0, metres, 0), Eigen::Vector3d(0, -metres, 0)}) {
    const auto q = camera.project(p + offset);
    if (q) pixels = std::max(pixels, (*q - centre).lpNorm<Eigen::Infinity>());
  }
  return pixels;
}

std::optional<SearchWindow> window(const CameraModel& camera, const Eigen::Vector3d& p, double grow_metres,
                                   const SearchWindowParams& params) {
  const auto centre = camera.project(p);
  if (!centre || !centre->allFinite()) return std::nullopt;
  const double half =
      std::min(0.5 * params.side_px + pixelsFor(camera, p, *centre, grow_metres), 0.5 * params.max_side_px);
  const auto rect = squareAbout(*centre, half, cv::Size(camera.width(), camera.height()));
  if (!rect) return std::nullopt;  // entirely outside the image
  SearchWindow w;
  w.rect = *rect;
  w.centre = *centre;
  w.expected = camera.inImage(*centre, params.expected_margin_px);
  return w;
}

}  // namespace

std::optional<cv::Rect> squareAbout(const Eigen::Vector2d& centre, double half, cv::Size image) {
  if (!centre.allFinite() || !std::isfinite(half)) return std::nullopt;
  // Clipped as doubles first: a centre far beyond the image must not overflow an int.
  const double x0 = std::max(0.0, std::ceil(centre.x() - half));
  const double y0 = std::max(0.0, std::ceil(centre.y() - half));
  const double x1 = std::min<double>(image.width, std::ceil(centre.x() + half));
  const double y1 = std::min<double>(image.height, std::ceil(centre.y() + half));
  if (x1 <= x0 || y1 <= y0) return std::nullopt;
  return cv::Rect(static_cast<int>(x0), static_cast<int>(y0), static_cast<int>(x1 - x0),
                  static_cast<int>(y1 - y0));
}

void validate(const SearchWindowParams& p) {
  if (p.side_px < 1) throw std::invalid_argument("search windows: side_px must be >= 1");
  if (p.max_side_px < p.side_px)
    throw std::invalid_argument("search windows: max_side_px must be >= side_px");
  if (!(p.sigma_scale >= 0)) throw std::invalid_argument("search windows: sigma_scale must be >= 0");
  if (!(p.ball_speed_margin >= 0))
    throw std::invalid_argument("search windows: ball_speed_margin must be >= 0");
  if (!std::isfinite(p.robot_height[0]) || !std::isfinite(p.robot_height[1]) ||
      !std::isfinite(p.ball_height)) {
    throw std::invalid_argument("search windows: heights must be finite");
  }
}

std::vector<SearchWindow> searchWindows(const TrackerOutput& predicted, const CameraModel& camera,
                                        double frame_interval, const SearchWindowParams& params) {
  validate(params);
  frame_interval = std::isfinite(frame_interval) ? std::max(0.0, frame_interval) : 0.0;
  std::vector<SearchWindow> out;
  for (const auto& r : predicted.robots) {
    const double grow = params.sigma_scale * largestSigma(r.position_covariance);
    auto w = window(camera, {r.x, r.y, heightOf(params.robot_height, r.team)}, grow, params);
    if (!w) continue;
    w->target = SearchWindow::Target::Robot;
    w->track_id = r.track_id;
    w->team = r.team;
    w->id = r.id;
    out.push_back(*w);
  }
  for (const auto& b : predicted.balls) {
    if (!b.primary && !params.alternative_balls) continue;
    const double speed = std::hypot(b.vx, b.vy);
    const double grow = params.sigma_scale * largestSigma(b.position_covariance) +
                        params.ball_speed_margin * speed * frame_interval;
    auto w = window(camera, {b.x, b.y, params.ball_height}, grow, params);
    if (!w) continue;
    w->target = SearchWindow::Target::Ball;
    w->track_id = b.track_id;
    w->primary_ball = b.primary;
    w->last_measured = b.last_measured;
    w->expected = w->expected && b.primary;  // alternatives come and go: not "expected"
    out.push_back(*w);
  }
  return out;
}

std::vector<cv::Rect> windowRects(const std::vector<SearchWindow>& windows) {
  std::vector<cv::Rect> rects;
  rects.reserve(windows.size());
  for (const auto& w : windows) rects.push_back(w.rect);
  return rects;
}

}  // namespace soccer_vision

namespace soccer_vision {

std::vector<cv::Rect> entryBands(cv::Size image, int band_px) {
  if (band_px <= 0 || image.width <= 0 || image.height <= 0) return {};
  const int b = std::min({band_px, image.width / 2, image.height / 2});
  const int inner = image.height - 2 * b;
  std::vector<cv::Rect> bands = {{0, 0, image.width, b}, {0, image.height - b, image.width, b}};
  if (inner > 0) {
    bands.emplace_back(0, b, b, inner);
    bands.emplace_back(image.width - b, b, b, inner);
  }
  return bands;
}

}  // namespace soccer_vision
