// Robots from regions (paper §III-D, generalised): every region is projected onto the
// marker plane through the camera model (PatternSet::height: a team-colour region onto its
// team's, an id-colour region onto each team's, read by the hypotheses of that team;
// the expected areas and the robots' pixels at their team's too); for each team-colour
// region, hypotheses are formed from id-colour regions at distances and angles the
// pattern allows (seed: one id marker taken as one slot fixes the heading; then every
// slot is predicted and the nearest unused region within the gate taken), the robot pose
// is fitted to all of them (weighted 2-D Procrustes, the team tag's minor axis pulling
// the heading for elongated team tags) and scored by
//   - the geometric residual of every marker against where the fitted pose puts it,
//   - the team tag's axis against the fitted heading (modulo pi: the 180° ambiguity of
//     the axis is resolved by the id markers),
//   - area plausibility: observed pixel area against the marker's outline projected
//     through the camera at that place,
//   - completeness (missing id markers).
// A global assignment then picks hypotheses best-confidence-first such that no region
// is used twice and no (team, id) appears twice; a team region whose best hypothesis was
// blocked by an accepted one is re-hypothesised without the taken regions. This is the
// paper's minimum-sum-of-distances pairing with gating instead of unconditional pairing.
//
// Ids come from the colours of the matched slots (PatternSet::ids). With a missing slot
// the id is given only when exactly one id is compatible with the slots seen, or when
// this camera identified a robot of the team with one of the compatible ids where this one
// is, facing its way, in its last frames (RecentIdentities); with the
// two-tag pattern a robot whose role tag is missing has no id and no heading: it is not
// reported (or, with report_unidentified, reported with id -1, heading_valid = false and
// a confidence of at most 0.2). A wrong id is never preferred to no id.
// Team-only patterns: team and position per team region, heading_valid = false, id -1.
#pragma once

#include <vector>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/identification/recent_identities.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

struct RobotIdentificationParams {
  double marker_gate = 0.020;     // m: max distance of a marker from where the fitted pose puts it
  double position_sigma = 0.004;  // m: marker centroid scatter expected (scoring scale)
  double axis_gate_deg = 20.0;    // deg: max team-tag minor axis vs fitted heading (mod 180°)
  double axis_sigma_deg = 4.0;    // deg: scoring scale of that difference
  double axis_weight = 0.25;      // share of the team-tag axis in the heading (0 = markers only)
  double min_elongation = 1.6;    // team region sqrt(eigenvalue ratio) needed to use its axis
  // Observed / expected pixel area within [1/g, g]. Blurred and noisy markers are small: a
  // 40 mm disc moving 20 mm per exposure keeps only its fully covered core in the colour
  // class (0.17-0.4 of the expected area; the blend with the black top is darker than any
  // calibration sample), and under Bayer noise + JPEG a few of its ~13 quads are missed
  // (~0.3). 2.5 rejected them: 83 % of the robots identified per flicker_noise frame and
  // 98.6 % of fast_motion's; 3.5: 91 % and 99.1 %, no identity error on any preset. The
  // team marker of a complete pattern of three or more id markers: within [1/g², g²].
  double area_ratio_gate = 3.5;
  double area_sigma = 0.35;  // scoring scale of ln(observed / expected area)
  // A robot one of whose markers lies where the fit puts it but is smaller than its gate,
  // in [1/g², 1/g) of its area (a moving robot's blurred markers): reported with at most
  // this confidence, below the tracker's min_start_confidence (0.2): it measures the track
  // of its robot (or, misread, the one it lies on) and begins none. 0 = such a robot is
  // rejected (`area`).
  double small_marker_confidence = 0.15;
  // A robot whose markers fit several ids (a missing SSL dot, a two-tag role disc unseen)
  // takes the one of them that the robot of its team last seen there had
  // (RecentIdentities), with at most recalled_confidence: it measures its track and begins
  // none.
  RecallParams recall;
  double recalled_confidence = 0.15;
  int max_missing_markers = 1;         // id markers a robot may lack and still be reported
  double missing_marker_factor = 0.5;  // confidence factor per missing id marker
  double min_confidence = 0.05;        // hypotheses below are dropped
  bool report_unidentified = false;    // report team markers whose id is unknown (id -1)
};

struct RobotIdentificationResult {
  std::vector<RobotDetection> robots;     // by decreasing confidence
  std::vector<bool> region_used;          // per input region: part of a reported robot
  std::vector<double> region_confidence;  // per input region: that robot's confidence (0: none)
  // Team-colour regions that ended in no robot, by the furthest check their best
  // hypothesis passed (Unpaired: none formed; Conflict: a better robot took its regions).
  RejectionCounts rejections;
  int recalled_ids = 0;         // reported robots whose id was recalled (RecentIdentities)
  int small_marker_robots = 0;  // reported robots with a marker below its area gate
  // Those of them that were projected, each with its cause, as `rejections` counts it.
  std::vector<RejectedRobotCandidate> rejected;
};

class RobotIdentifier {
 public:
  RobotIdentifier(const CameraModel& camera, const PatternSet& patterns,
                  const RobotIdentificationParams& params = {});
  const RobotIdentificationParams& params() const { return params_; }
  void setParams(const RobotIdentificationParams& params) { params_ = params; }
  const PatternSet& patterns() const { return patterns_; }
  const CameraModel& camera() const { return camera_; }

  // Regions in raw image pixel coordinates (SegmentationResult::regions). With `recent`
  // (this camera's memory; the frame's capture `stamp`), a robot whose markers fit several
  // ids may take one from it, and the frame's identified robots are remembered.
  RobotIdentificationResult identify(const std::vector<Region>& regions, RecentIdentities* recent = nullptr,
                                     double stamp = 0) const;

 private:
  CameraModel camera_;
  PatternSet patterns_;
  RobotIdentificationParams params_;
};

}  // namespace soccer_vision
