// The whole vision pipeline in one process, without ROS: what the nodelets of one manager
// do between an image and the tracked robots (Segmentation -> Identification -> Tracking
// -> search windows back to Segmentation), frame by frame, deterministically: results
// depend on the images and their stamps only, never on the clock. The offline evaluation
// and the pipeline benchmark run it; it makes the same decisions as the nodelets with the
// same parameters (frame_step per camera; per camera a SearchPlanner, as in the Tracking
// nodelet; windows older than the Segmentation nodelet's window_max_age are stale).
//
// Per camera frame: process(camera, image, stamp) -> PipelineFrame (skipped by frame_step,
// or: the detections, the tracker output at the stamp, how the frame was searched and the
// time of each stage). One Tracker serves all cameras (a robot in the overlap is one track).
#pragma once

#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/segmentation/online_calibration.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/tracking/frame_step.h"
#include "soccer_vision/tracking/search_planner.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

struct VisionPipelineParams {
  int frame_step = 1;          // process every n-th frame of each camera (>= 1)
  SearchPlannerParams search;  // windows (search.windows.side_px = R), entry bands, policy
  SegmentationParams segmentation;
  IdentificationParams identification;
  TrackerParams tracker;
  // Per camera, learned from its confirmed markers and carpet after each frame (off by
  // default); its updates replace the camera's segmentation model.
  OnlineCalibrationParams online_calibration;
};

void validate(const VisionPipelineParams& p);  // throws std::invalid_argument

struct PipelineCamera {
  int id = 0;                                             // camera_id of its detections
  CameraModel model;                                      // intrinsics + pose in `field`
  std::shared_ptr<const SegmentationModel> segmentation;  // colour table + illumination reference
  PixelLayout layout = PixelLayout::Bgr;
};

// Table II's stages [ms]: preprocessing = illumination adaptation; classification = pixel
// classification; recognition = morphology + regions + identification (robots, ball, pose);
// tracking = Kalman update + output + the next frame's windows and search decision.
struct PipelineTimings {
  double preprocessing = 0, classification = 0, recognition = 0, tracking = 0;
  double total() const { return preprocessing + classification + recognition + tracking; }
};

struct PipelineFrame {
  int camera_id = 0;
  double stamp = 0;
  bool processed = false;     // false: skipped by frame_step (nothing else is set)
  bool global_search = true;  // this frame was searched whole
  // Why it was searched whole (None: in windows; Periodic for every frame when search
  // windows are off; AfterReset when the windows were stale: a gap in the stamps).
  GlobalSearchReason search_reason = GlobalSearchReason::First;
  std::size_t windows = 0;  // rectangles searched (windows + entry bands)
  PipelineTimings times;
  CameraFrameDetections detections;
  std::vector<Region> regions;  // the segmented regions identification saw (image pixels)
  // The tracks predicted to this stamp before this frame's measurements (the Kalman
  // prediction the windows were made from; paper Fig. 6), and the output after them.
  TrackerOutput prediction;
  TrackerOutput output;
  bool tracker_reset = false;  // the stamps jumped: all tracks were dropped first
};

class VisionPipeline {
 public:
  // Throws std::invalid_argument for bad params, no cameras, duplicate ids or a camera
  // without a segmentation model.
  VisionPipeline(std::vector<PipelineCamera> cameras, const PatternSet& patterns, const FieldGeometry& field,
                 const VisionPipelineParams& params = {});

  // One frame of camera `camera_id` (throws std::invalid_argument for an unknown camera or
  // an image that does not fit its layout).
  PipelineFrame process(int camera_id, const cv::Mat& image, double stamp);

  const Tracker& tracker() const { return tracker_; }
  const VisionPipelineParams& params() const { return params_; }
  const std::vector<PipelineCamera>& cameras() const { return cameras_; }
  const PipelineCamera* camera(int camera_id) const;  // nullptr for an unknown camera
  // The online self-calibration of a camera (nullptr for an unknown camera).
  const OnlineCalibration* onlineCalibration(int camera_id) const;

 private:
  struct CameraState {
    CameraState(FrameIdentifier id, const VisionPipelineParams& p,
                std::shared_ptr<const SegmentationModel> model)
        : identifier(std::move(id)),
          frame_step(p.frame_step),
          planner(p.search),
          learning(std::move(model), p.online_calibration) {}
    FrameIdentifier identifier;
    FrameStep frame_step;
    SearchPlanner planner;
    OnlineCalibration learning;
    std::vector<int> confirmed;      // scratch: the regions identification confirmed
    RecentIdentities recent;         // the robots identification saw in this camera's last frames
    std::optional<SearchPlan> next;  // for the next processed frame; none before the first
  };

  std::vector<PipelineCamera> cameras_;
  VisionPipelineParams params_;
  std::vector<CameraState> state_;
  Segmenter segmenter_;
  SegmentationResult segmented_;
  Tracker tracker_;
};

}  // namespace soccer_vision
