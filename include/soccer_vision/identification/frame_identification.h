// Identification of one camera frame: regions (raw image pixels, as segmentation gives
// them) -> robots and ball candidates in `field` (CameraFrameDetections). Robots first
// (RobotIdentifier); the ball from the orange regions no robot took (BallDetector).
#pragma once

#include <vector>

#include "soccer_vision/common/detections.h"
#include "soccer_vision/identification/ball_detection.h"
#include "soccer_vision/identification/robot_identification.h"

namespace soccer_vision {

struct IdentificationParams {
  RobotIdentificationParams robots;
  BallDetectionParams balls;
  // Robots reported with at least this confidence have their marker regions confirmed:
  // online self-calibration learns from them (a robot lacking a marker has at most 0.5).
  double confirm_confidence = 0.7;
};

class FrameIdentifier {
 public:
  FrameIdentifier(const CameraModel& camera, const PatternSet& patterns, const FieldGeometry& field,
                  const IdentificationParams& params = {});
  void setParams(const IdentificationParams& params);
  const IdentificationParams& params() const { return params_; }
  const CameraModel& camera() const { return robots_.camera(); }

  // `confirmed` (optional): set to the indices of the regions that belong to robots
  // reported with at least confirm_confidence. `recent` (optional): the camera's memory of
  // identified robots, read for markers that fit several ids and updated with this frame's.
  CameraFrameDetections identify(const std::vector<Region>& regions, double stamp = 0, int camera_id = 0,
                                 bool global_search = true, std::vector<int>* confirmed = nullptr,
                                 RecentIdentities* recent = nullptr) const;

 private:
  IdentificationParams params_;
  RobotIdentifier robots_;
  BallDetector balls_;
};

}  // namespace soccer_vision
