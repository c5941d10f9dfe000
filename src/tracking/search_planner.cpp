#include "soccer_vision/tracking/search_planner.h"

#include <cmath>
#include <stdexcept>

namespace soccer_vision {

void validate(const SearchPlannerParams& p) {
  if (p.entry_band_px < 0) throw std::invalid_argument("entry_band_px must be >= 0");
  if (!(p.ball_streak_intervals >= 0) || !std::isfinite(p.ball_streak_intervals))
    throw std::invalid_argument("ball_streak_intervals must be finite and >= 0");
  validate(p.global_search);
  validate(p.windows);
}

namespace {

// With the sweep the policy has no period of its own: the stripes are the periodic search.
GlobalSearchParams policyParams(const SearchPlannerParams& p) {
  GlobalSearchParams g = p.global_search;
  if (p.sweep && p.search_windows) g.period_frames = 0;
  return g;
}

}  // namespace

cv::Rect sweepStripe(cv::Size image, int index, int count, int margin) {
  if (count <= 0 || image.height <= 0) return {};
  index = ((index % count) + count) % count;
  const long h = image.height;
  const int top = static_cast<int>(h * index / count) - margin;
  const int bottom = static_cast<int>(h * (index + 1) / count) + margin;
  return cv::Rect(0, top, image.width, bottom - top) & cv::Rect(0, 0, image.width, image.height);
}

SearchPlanner::SearchPlanner(const SearchPlannerParams& params)
    : params_(params), policy_(policyParams(params)) {
  validate(params_);
}

void SearchPlanner::setParams(const SearchPlannerParams& params) {
  validate(params);
  params_ = params;
  policy_.setParams(policyParams(params));
}

void SearchPlanner::observe(const TrackerUpdateReport& report, double stamp, bool searched_whole) {
  policy_.observe(report, searched_whole);
  if (!report.processed()) return;  // a late or invalid frame says nothing of the rate
  if (last_stamp_ > 0 && stamp > last_stamp_) {
    const double dt = stamp - last_stamp_;
    interval_ = interval_ > 0 ? 0.9 * interval_ + 0.1 * dt : dt;
  }
  last_stamp_ = stamp;
}

SearchPlan SearchPlanner::plan(const Tracker& tracker, const CameraModel* camera, double stamp) {
  SearchPlan plan;
  plan.stamp = stamp + interval();
  if (params_.search_windows && camera) {
    plan.windows = searchWindows(tracker.predictions(plan.stamp), *camera, interval(), params_.windows);
  }
  // The policy sees every frame, so that its period and its expected targets stay current.
  plan.reason = policy_.decide(plan.windows, tracker.numRobotTracks() + tracker.numBallTracks());
  for (const SearchWindow& w : plan.windows) {
    if (w.primary_ball && plan.stamp - w.last_measured <= params_.ball_streak_intervals * interval())
      plan.ball_streak_rects.push_back(w.rect);
  }
  if (!params_.search_windows) plan.reason = GlobalSearchReason::Periodic;
  plan.global_search = !camera || plan.reason != GlobalSearchReason::None;
  if (plan.global_search) return plan;
  plan.rects = windowRects(plan.windows);
  const cv::Size image(camera->width(), camera->height());
  for (const cv::Rect& band : entryBands(image, params_.entry_band_px)) plan.rects.push_back(band);
  const int stripes = params_.global_search.period_frames;
  if (params_.sweep && stripes > 0) {
    plan.sweep_stripe = sweepStripe(image, next_stripe_, stripes, params_.entry_band_px);
    next_stripe_ = (next_stripe_ + 1) % stripes;
    if (!plan.sweep_stripe.empty()) plan.rects.push_back(plan.sweep_stripe);
  }
  return plan;
}

}  // namespace soccer_vision
