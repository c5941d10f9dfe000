#include "soccer_vision/tracking/search_planner.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace soccer_vision {

void validate(const SearchPlannerParams& p) {
  if (p.entry_band_px < 0) throw std::invalid_argument("entry_band_px must be >= 0");
  if (!(p.ball_streak_intervals >= 0) || !std::isfinite(p.ball_streak_intervals))
    throw std::invalid_argument("ball_streak_intervals must be finite and >= 0");
  if (p.candidate_frames < 0) throw std::invalid_argument("candidate_frames must be >= 0");
  if (p.max_candidates < 0) throw std::invalid_argument("max_candidates must be >= 0");
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

cv::Rect playingAreaImageRect(const CameraModel& camera, const FieldGeometry& field) {
  // Points along the lines' outer edges, so that a distorted image of them is enclosed.
  constexpr int kSteps = 24;
  const double hx = field.halfLength() + field.line_width, hy = field.halfWidth() + field.line_width;
  double u0 = HUGE_VAL, v0 = HUGE_VAL, u1 = -HUGE_VAL, v1 = -HUGE_VAL;
  for (int i = 0; i <= kSteps; ++i) {
    const double t = -1.0 + 2.0 * i / kSteps;
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(t * hx, -hy, 0), Eigen::Vector3d(t * hx, hy, 0),
                                     Eigen::Vector3d(-hx, t * hy, 0), Eigen::Vector3d(hx, t * hy, 0)}) {
      const auto px = camera.project(p);
      if (!px || !std::isfinite(px->x()) || !std::isfinite(px->y())) continue;
      u0 = std::min(u0, px->x());
      v0 = std::min(v0, px->y());
      u1 = std::max(u1, px->x());
      v1 = std::max(v1, px->y());
    }
  }
  const cv::Rect image(0, 0, camera.width(), camera.height());
  if (!(u0 <= u1 && v0 <= v1)) return {};
  const auto clamp = [](double x, int hi) {
    return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(hi)));
  };
  const int x0 = clamp(std::floor(u0), image.width), y0 = clamp(std::floor(v0), image.height);
  const int x1 = clamp(std::ceil(u1) + 1, image.width), y1 = clamp(std::ceil(v1) + 1, image.height);
  return cv::Rect(x0, y0, x1 - x0, y1 - y0) & image;
}

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

bool lookAgainAt(const RejectedRobotCandidate& c) {
  return c.cause != RejectionCause::Projection && c.cause != RejectionCause::Unpaired && std::isfinite(c.u) &&
         std::isfinite(c.v);
}

void SearchPlanner::observe(const TrackerUpdateReport& report, double stamp, bool searched_whole,
                            const std::vector<RejectedRobotCandidate>& rejected) {
  policy_.observe(report, searched_whole);
  if (!report.processed()) return;          // a late or invalid frame says nothing of the rate
  if (report.reset()) candidates_.clear();  // seen on the old time line
  for (Candidate& c : candidates_) --c.frames_left;
  for (const RejectedRobotCandidate& r : rejected) {
    if (!lookAgainAt(r) || params_.candidate_frames == 0) continue;
    const Eigen::Vector2d pixel(r.u, r.v);
    // Rejected again where it was looked for (within a quarter window): the same candidate.
    auto same = std::find_if(candidates_.begin(), candidates_.end(), [&](const Candidate& c) {
      return (c.pixel - pixel).norm() <= 0.25 * params_.windows.side_px;
    });
    if (same != candidates_.end())
      *same = {pixel, params_.candidate_frames};
    else if (static_cast<int>(candidates_.size()) < params_.max_candidates)
      candidates_.push_back({pixel, params_.candidate_frames});
  }
  candidates_.erase(std::remove_if(candidates_.begin(), candidates_.end(),
                                   [](const Candidate& c) { return c.frames_left <= 0; }),
                    candidates_.end());
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
  for (const Candidate& c : candidates_) {
    // Beyond the image or not a number (another node's message may say anything): no window.
    const auto around = squareAbout(c.pixel, 0.5 * params_.windows.side_px, image);
    if (around) plan.rects.push_back(*around);
  }
  const std::vector<cv::Rect> bands = entryBands(image, params_.entry_band_px);
  plan.rects.insert(plan.rects.end(), bands.begin(), bands.end());
  const int stripes = params_.global_search.period_frames;
  if (params_.sweep && stripes > 0) {
    plan.sweep_stripe = sweepStripe(image, next_stripe_, stripes, params_.entry_band_px);
    next_stripe_ = (next_stripe_ + 1) % stripes;
    if (!plan.sweep_stripe.empty()) plan.rects.push_back(plan.sweep_stripe);
  }
  if (params_.lost_ball_sweep_streaks && plan.ball_streak_rects.empty() && !plan.sweep_stripe.empty() &&
      tracker.params().field) {
    // The entry bands and the stripe: a fast ball comes into view through a band.
    const cv::Rect play = playingAreaImageRect(*camera, *tracker.params().field);
    auto addInPlay = [&](const cv::Rect& r) {
      if (!(r & play).empty()) plan.lost_ball_streak_rects.push_back(r & play);
    };
    for (const cv::Rect& band : bands) addInPlay(band);
    addInPlay(plan.sweep_stripe);
  }
  return plan;
}

}  // namespace soccer_vision
