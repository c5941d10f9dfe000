#include "soccer_vision/identification/ball_detection.h"

#include <algorithm>
#include <cmath>

#include "soccer_vision/identification/image_footprint.h"

namespace soccer_vision {

BallDetector::BallDetector(const CameraModel& camera, const FieldGeometry& field,
                           const BallDetectionParams& params)
    : camera_(camera), field_(field), params_(params) {}

std::vector<BallDetection> BallDetector::detect(const std::vector<Region>& regions,
                                                const std::vector<bool>& region_used) const {
  // Orange fragments near each other are one ball: a ball faster than its own diameter per
  // exposure is a streak that segmentation may cut into pieces (its faint middle).
  struct Fragment {
    Eigen::Vector2d pixel;
    Eigen::Vector2d field;
    double area;
  };
  std::vector<Fragment> fragments;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const Region& region = regions[r];
    if (region.color != params_.color || (r < region_used.size() && region_used[r])) continue;
    if (region.area == 0 || !std::isfinite(region.cx) || !std::isfinite(region.cy)) continue;
    const Eigen::Vector2d pixel(region.cx, region.cy);
    const auto p = camera_.pixelToField(pixel, params_.radius);
    if (p && p->allFinite()) fragments.push_back({pixel, p->head<2>(), static_cast<double>(region.area)});
  }
  std::vector<int> cluster(fragments.size());
  for (std::size_t i = 0; i < fragments.size(); ++i) cluster[i] = static_cast<int>(i);
  auto root = [&](int i) {
    while (cluster[i] != i) i = cluster[i] = cluster[cluster[i]];
    return i;
  };
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    for (std::size_t j = i + 1; j < fragments.size(); ++j) {
      if ((fragments[i].field - fragments[j].field).norm() <= params_.merge_distance) {
        cluster[root(static_cast<int>(j))] = root(static_cast<int>(i));
      }
    }
  }
  std::vector<BallDetection> out;
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    if (root(static_cast<int>(i)) != static_cast<int>(i)) continue;
    double area = 0;
    Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
    for (std::size_t j = 0; j < fragments.size(); ++j) {
      if (root(static_cast<int>(j)) != static_cast<int>(i)) continue;
      area += fragments[j].area;
      pixel += fragments[j].area * fragments[j].pixel;
    }
    pixel /= area;
    const auto p = camera_.pixelToField(pixel, params_.radius);
    if (!p || !field_.onCarpet(p->x(), p->y(), params_.field_margin)) continue;
    const double expected = expectedBallArea(camera_, *p, params_.radius);
    if (expected <= 0) continue;
    const double ratio = area / expected;
    if (ratio < params_.area_ratio_min || ratio > params_.area_ratio_max) continue;
    const double l = std::log(ratio) / params_.area_sigma;
    BallDetection b;
    b.x = p->x();
    b.y = p->y();
    b.z = params_.radius;
    b.confidence = std::exp(-0.5 * l * l);
    b.pixel = pixel;
    b.area_px = area;
    if (b.confidence >= params_.min_confidence) out.push_back(b);
  }
  std::sort(out.begin(), out.end(),
            [](const BallDetection& a, const BallDetection& b) { return a.confidence > b.confidence; });
  if (params_.max_candidates > 0 && static_cast<int>(out.size()) > params_.max_candidates) {
    out.resize(params_.max_candidates);
  }
  return out;
}

}  // namespace soccer_vision
