#include "soccer_vision/tracking/search_planner.h"

#include <stdexcept>

namespace soccer_vision {

void validate(const SearchPlannerParams& p) {
  if (p.entry_band_px < 0) throw std::invalid_argument("entry_band_px must be >= 0");
  validate(p.global_search);
  validate(p.windows);
}

SearchPlanner::SearchPlanner(const SearchPlannerParams& params)
    : params_(params), policy_(params.global_search) {
  validate(params_);
}

void SearchPlanner::setParams(const SearchPlannerParams& params) {
  validate(params);
  params_ = params;
  policy_.setParams(params.global_search);
}

void SearchPlanner::observe(const TrackerUpdateReport& report, double stamp) {
  policy_.observe(report);
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
  if (!params_.search_windows) plan.reason = GlobalSearchReason::Periodic;
  plan.global_search = !camera || plan.reason != GlobalSearchReason::None;
  if (plan.global_search) return plan;
  plan.rects = windowRects(plan.windows);
  for (const cv::Rect& band :
       entryBands(cv::Size(camera->width(), camera->height()), params_.entry_band_px)) {
    plan.rects.push_back(band);
  }
  return plan;
}

}  // namespace soccer_vision
