// The measured rate: of the robots a camera frame shows (ground truth visible and all their
// markers inside that camera's image, the truth's own rule: markerOutlinePoints), the share
// the frame's own detections measure -- same team and id within 50 mm -- as opposed to
// tracks coasting on predictions. The others by why they were missed, in this order:
//   wrong id:                 a detection within 50 mm, of another team or id;
//   identification rejected:  a region of a marker colour lies on the robot's top in the
//                             image, yet no detection came of it. Why: the identification's
//                             cause when a rejected team region lies there; else "no team
//                             region" when none of a team colour does (its team marker read
//                             as another colour), else "team region used" (a robot
//                             elsewhere took it);
//   nothing segmented:        not even a marker-coloured region there.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/robot_pattern.h"

namespace soccer_vision {

// The causes of an identification miss without a rejected team region on the top.
constexpr const char* kNoTeamRegion = "no_team_region";
constexpr const char* kTeamRegionUsed = "team_region_used";

struct MeasuredRate {
  std::int64_t visible = 0;  // robot-frames: visible robots summed over camera frames
  std::int64_t measured = 0;
  std::int64_t wrong_id = 0;
  std::int64_t identification_rejected = 0;
  RejectionCounts rejected_by_cause;  // of identification_rejected: a rejected team region's cause
  std::int64_t no_team_region = 0;    // of identification_rejected: no team-coloured region on its top
  std::int64_t team_region_used = 0;  // of identification_rejected: one, not rejected, taken elsewhere
  std::int64_t nothing_segmented = 0;
  double rate() const { return visible > 0 ? static_cast<double>(measured) / visible : 1.0; }
};

// One visible robot a camera frame did not measure: where and why, to look at.
struct MissedRobot {
  double stamp = 0;  // the frame's capture stamp
  int camera_id = 0;
  Team team = Team::Blue;
  int id = 0;
  const char* cause = "";       // "wrong_id", "identification_rejected" or "nothing_segmented"
  const char* rejection = "";   // identification_rejected: the cause of a rejected team region on
                                // its top ("area", "unpaired", ...), else "no_team_region" or
                                // "team_region_used"
  Eigen::Vector2d pixel{0, 0};  // its top's centre in the image
};

// A region of a robot marker colour, as the measured rate looks at it: its image centroid
// and whether its colour is a team's.
struct MarkerRegionCentre {
  Eigen::Vector2d pixel{0, 0};
  bool team = false;
};

class MeasuredRateCounter {
 public:
  // `patterns`: the robots' markers, heights and radius.
  explicit MeasuredRateCounter(PatternSet patterns = PatternSet::twoTag(), double match_distance = 0.05);

  // One processed camera frame: the truth at its stamp, the camera, the frame's own robot
  // detections, the image centroids of its regions of marker colours (team and id) and the
  // robot candidates identification rejected.
  void add(const FrameRecord& truth, const CameraModel& camera, const std::vector<RobotDetection>& detections,
           const std::vector<MarkerRegionCentre>& marker_regions, int camera_id = 0,
           const std::vector<RejectedRobotCandidate>& rejected = {});

  const MeasuredRate& total() const { return total_; }
  // The same counts per robot (team, id): which robot a scene loses, not only how often.
  const std::map<std::pair<Team, int>, MeasuredRate>& byRobot() const { return by_robot_; }
  // Every miss, in the order added.
  const std::vector<MissedRobot>& misses() const { return misses_; }

 private:
  PatternSet patterns_;
  double match_distance_;
  MeasuredRate total_;
  std::map<std::pair<Team, int>, MeasuredRate> by_robot_;
  std::vector<MissedRobot> misses_;
};

}  // namespace soccer_vision
