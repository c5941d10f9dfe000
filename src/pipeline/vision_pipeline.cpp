#include "soccer_vision/pipeline/vision_pipeline.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>
#include <string>

namespace soccer_vision {

namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// The Segmentation nodelet's window_max_age: windows planned for a much older stamp are
// stale (a paused or skipped stream) and the frame is searched whole.
constexpr double kWindowMaxAge = 0.5;  // [s]

}  // namespace

void validate(const VisionPipelineParams& p) {
  if (p.frame_step < 1) throw std::invalid_argument("frame_step must be >= 1");
  validate(p.search);
  validate(p.tracker);
  p.online_calibration.validate();
}

namespace {
// The tracker tells the ball from still orange objects by the lines with the field's
// playing area: the pipeline's field, unless the parameters name one.
TrackerParams withField(TrackerParams p, const FieldGeometry& field) {
  if (!p.field) p.field = field;
  return p;
}

// A robot's window is centred where its team's marker plane puts it.
VisionPipelineParams withTeamHeights(VisionPipelineParams p, const PatternSet& patterns) {
  p.search.windows.robot_height = patterns.heights();
  return p;
}
}  // namespace

VisionPipeline::VisionPipeline(std::vector<PipelineCamera> cameras, const PatternSet& patterns,
                               const FieldGeometry& field, const VisionPipelineParams& params)
    : cameras_(std::move(cameras)),
      params_(withTeamHeights(params, patterns)),
      segmenter_(params.segmentation),
      tracker_(withField(params.tracker, field)) {
  validate(params_);
  if (cameras_.empty()) throw std::invalid_argument("VisionPipeline: no cameras");
  std::set<int> ids;
  for (const PipelineCamera& c : cameras_) {
    if (!ids.insert(c.id).second)
      throw std::invalid_argument("VisionPipeline: camera " + std::to_string(c.id) + " twice");
    if (!c.segmentation)
      throw std::invalid_argument("VisionPipeline: camera " + std::to_string(c.id) + " has no colour table");
    // A table calibrated at another resolution once switched illumination adaptation off
    // silently (50-83 % detection): refused, naming both sizes.
    const cv::Mat& reference = c.segmentation->illumination.reference();
    const int w = c.model.intrinsics().width, h = c.model.intrinsics().height;
    const cv::Size grid((w + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize,
                        (h + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize);
    if (!reference.empty() && reference.size() != grid) {
      throw std::invalid_argument("VisionPipeline: camera " + std::to_string(c.id) +
                                  ": the colour table was calibrated on frames of " +
                                  "another size (its illumination reference has " +
                                  std::to_string(reference.cols) + "x" + std::to_string(reference.rows) +
                                  " blocks of " + std::to_string(BlockOffsets::kBlockSize) + " px, " +
                                  std::to_string(w) + "x" + std::to_string(h) + " frames have " +
                                  std::to_string(grid.width) + "x" + std::to_string(grid.height) +
                                  "): calibrate the table at " + std::to_string(w) + "x" + std::to_string(h));
    }
    state_.emplace_back(FrameIdentifier(c.model, patterns, field, params_.identification), params_,
                        c.segmentation);
  }
}

const OnlineCalibration* VisionPipeline::onlineCalibration(int camera_id) const {
  const PipelineCamera* c = camera(camera_id);
  return c ? &state_[static_cast<std::size_t>(c - cameras_.data())].learning : nullptr;
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
  PipelineCamera& camera = cameras_[index];  // its segmentation model is replaced by what it learns
  CameraState& state = state_[index];

  PipelineFrame frame;
  frame.camera_id = camera_id;
  frame.stamp = stamp;
  if (!state.frame_step.process()) return frame;
  frame.processed = true;

  // No plan yet: the first frame is searched whole; a plan for a much older stamp is stale.
  const bool stale = state.next && stamp - state.next->stamp > kWindowMaxAge;
  const bool planned = state.next && !stale;
  static const std::vector<cv::Rect> kNone;  // of windows: the whole frame
  const std::vector<cv::Rect>& windows = planned ? state.next->rects : kNone;
  frame.search_reason = !state.next ? GlobalSearchReason::First
                        : stale && state.next->reason == GlobalSearchReason::None
                            ? GlobalSearchReason::AfterReset
                            : state.next->reason;

  const std::vector<cv::Rect> streak_windows =
      planned
          ? streakWindows(camera.layout, state.next->ball_streak_rects, state.next->lost_ball_streak_rects)
          : kNone;

  const auto t0 = Clock::now();
  segmenter_.process(*camera.segmentation, image, camera.layout, windows, segmented_, streak_windows);
  frame.global_search = segmented_.global_search;
  frame.windows = segmented_.windows.size();
  const bool learning = params_.online_calibration.enabled;
  frame.detections = state.identifier.identify(segmented_.regions, stamp, camera_id, segmented_.global_search,
                                               learning ? &state.confirmed : nullptr, &state.recent);
  const auto t1 = Clock::now();

  frame.prediction = tracker_.predictions(stamp);
  const TrackerUpdateReport report = tracker_.update(frame.detections);
  frame.tracker_reset = report.reset();
  if (report.reset()) {
    for (CameraState& s : state_) s.planner.restart();
  }
  state.planner.observe(report, stamp, frame.global_search, frame.detections.rejected_robots);
  frame.output = tracker_.output(stamp);
  state.next = state.planner.plan(tracker_, &camera.model, stamp);
  const auto t2 = Clock::now();
  // Outside the timed stages, as the nodelets learn on their own thread.
  if (learning) {
    state.learning.observe(image, camera.layout, segmented_.offsets, params_.segmentation.sharpen,
                           segmented_.regions, state.confirmed, stamp);
    if (auto learned = state.learning.update(stamp)) camera.segmentation = std::move(learned);
  }

  const SegmentationTimings& s = segmented_.timings;
  frame.times.preprocessing = s.illumination_ms;
  frame.times.classification = s.classification_ms;
  // Segmentation's morphology and regions, plus identification (its remaining time).
  frame.times.recognition = std::max(0.0, ms(t0, t1) - s.illumination_ms - s.classification_ms);
  frame.times.tracking = ms(t1, t2);
  frame.regions = segmented_.regions;  // outside the timed stages: for failure analysis only
  return frame;
}

}  // namespace soccer_vision
