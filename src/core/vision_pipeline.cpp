#include "soccer_vision/vision_pipeline.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>
#include <string>

namespace soccer_vision {

namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

// The Segmentation nodelet's window_max_age: windows planned for a much older stamp are
// stale (a paused or skipped stream) and the frame is searched whole.
constexpr double kWindowMaxAge = 0.5;  // [s]

}  // namespace

void validate(const VisionPipelineParams& p) {
  if (p.frame_step < 1) throw std::invalid_argument("frame_step must be >= 1");
  if (p.entry_band_px < 0) throw std::invalid_argument("entry_band_px must be >= 0");
  if (p.global_search.period_frames < 0) throw std::invalid_argument("global_search.period_frames must be >= 0");
  validate(p.windows);
  validate(p.tracker);
}

VisionPipeline::VisionPipeline(std::vector<PipelineCamera> cameras, const PatternSet& patterns,
                               const FieldGeometry& field, const VisionPipelineParams& params)
    : cameras_(std::move(cameras)), params_(params), segmenter_(params.segmentation), tracker_(params.tracker) {
  validate(params_);
  if (cameras_.empty()) throw std::invalid_argument("VisionPipeline: no cameras");
  std::set<int> ids;
  for (const PipelineCamera& c : cameras_) {
    if (!ids.insert(c.id).second) throw std::invalid_argument("VisionPipeline: camera " + std::to_string(c.id) + " twice");
    if (!c.segmentation) throw std::invalid_argument("VisionPipeline: camera " + std::to_string(c.id) + " has no colour table");
    state_.emplace_back(FrameIdentifier(c.model, patterns, field, params_.identification), params_);
  }
}

const PipelineCamera* VisionPipeline::camera(int camera_id) const {
  for (const PipelineCamera& c : cameras_) {
    if (c.id == camera_id) return &c;
  }
  return nullptr;
}

PipelineFrame VisionPipeline::process(int camera_id, const cv::Mat& image, double stamp) {
  const PipelineCamera* found = camera(camera_id);
  if (!found) throw std::invalid_argument("VisionPipeline: unknown camera " + std::to_string(camera_id));
  const std::size_t index = static_cast<std::size_t>(found - cameras_.data());
  const PipelineCamera& camera = *found;
  CameraState& state = state_[index];

  PipelineFrame frame;
  frame.camera_id = camera_id;
  frame.stamp = stamp;
  if (!state.frame_step.process()) return frame;
  frame.processed = true;

  const bool stale = state.last_stamp > 0 && stamp - (state.last_stamp + state.interval) > kWindowMaxAge;
  static const std::vector<cv::Rect> kWhole;
  const std::vector<cv::Rect>& windows = stale ? kWhole : state.windows;
  frame.search_reason = stale && state.next_reason == GlobalSearchReason::None ? GlobalSearchReason::AfterReset
                                                                                 : state.next_reason;

  const auto t0 = Clock::now();
  segmenter_.process(*camera.segmentation, image, camera.layout, windows, segmented_);
  frame.global_search = segmented_.global_search;
  frame.windows = segmented_.windows.size();
  frame.detections = state.identifier.identify(segmented_.regions, stamp, camera_id, segmented_.global_search);
  const auto t1 = Clock::now();

  frame.prediction = tracker_.output(stamp);
  const TrackerUpdateReport report = tracker_.update(frame.detections);
  frame.tracker_reset = report.reset();
  if (report.reset()) {
    for (CameraState& s : state_) s.policy.restart();
  }
  state.policy.observe(report);
  frame.output = tracker_.output(stamp);
  if (report.processed()) {
    if (state.last_stamp > 0 && stamp > state.last_stamp) {
      const double dt = stamp - state.last_stamp;
      state.interval = state.interval > 0 ? 0.9 * state.interval + 0.1 * dt : dt;
    }
    state.last_stamp = stamp;
  }
  planNextFrame(index, stamp);
  const auto t2 = Clock::now();

  const SegmentationTimings& s = segmented_.timings;
  frame.times.preprocessing = s.illumination_ms;
  frame.times.classification = s.classification_ms;
  // Segmentation's morphology and regions, plus identification (its remaining time).
  frame.times.recognition = std::max(0.0, ms(t0, t1) - s.illumination_ms - s.classification_ms);
  frame.times.tracking = ms(t1, t2);
  return frame;
}

// The windows for this camera's next processed frame, as the Tracking nodelet publishes them.
void VisionPipeline::planNextFrame(std::size_t index, double stamp) {
  CameraState& state = state_[index];
  const PipelineCamera& camera = cameras_[index];
  const double interval = state.interval > 0 ? state.interval : 1.0 / 60;
  std::vector<SearchWindow> next;
  if (params_.search_windows) {
    next = searchWindows(tracker_.output(stamp + interval), camera.model, interval, params_.windows);
  }
  const GlobalSearchReason reason = state.policy.decide(next, tracker_.numRobotTracks() + tracker_.numBallTracks());
  state.windows.clear();
  state.next_reason = params_.search_windows ? reason : GlobalSearchReason::Periodic;
  if (!params_.search_windows || reason != GlobalSearchReason::None) return;
  state.windows = windowRects(next);
  for (const cv::Rect& band : entryBands(cv::Size(camera.model.width(), camera.model.height()), params_.entry_band_px)) {
    state.windows.push_back(band);
  }
}

}  // namespace soccer_vision
