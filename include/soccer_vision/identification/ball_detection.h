// Ball candidates (paper §III-D / issue 4): orange regions that no robot pattern used,
// projected to the plane of the ball centre (21.5 mm), fragments within merge_distance of
// each other joined (a ball moving more than its diameter per exposure is a streak that
// segmentation may cut in pieces), kept when they lie on the carpet
// (plus a margin) and their pixel area is plausible for a 43 mm sphere at that place of
// the image (its silhouette projected through the camera model). Several candidates may
// remain; each gets a confidence from its area ratio, best first.
#pragma once

#include <vector>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

struct BallDetectionParams {
  ColorClass color = ColorClass::Orange;
  double radius = 0.0215;       // m; the centre is assumed at this height too
  double area_ratio_min = 0.3;  // observed / expected pixel area (motion blur, partial occlusion)
  double area_ratio_max = 3.0;
  double area_sigma = 0.5;       // scoring scale of ln(observed / expected area)
  double field_margin = 0.10;    // m beyond the carpet (playing area + boundary)
  double merge_distance = 0.06;  // m: orange fragments closer than this are one ball
  int max_candidates = 4;        // best first; 0 = all
  double min_confidence = 0.02;
};

class BallDetector {
 public:
  BallDetector(const CameraModel& camera, const FieldGeometry& field, const BallDetectionParams& params = {});
  const BallDetectionParams& params() const { return params_; }
  void setParams(const BallDetectionParams& params) { params_ = params; }

  // `region_used`: per region, true when a robot took it (empty = none taken).
  std::vector<BallDetection> detect(const std::vector<Region>& regions,
                                    const std::vector<bool>& region_used = {}) const;

 private:
  CameraModel camera_;
  FieldGeometry field_;
  BallDetectionParams params_;
};

}  // namespace soccer_vision
