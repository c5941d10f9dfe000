#include "soccer_vision/evaluation/measured_rate.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace soccer_vision {

MeasuredRateCounter::MeasuredRateCounter(PatternSet patterns, double match_distance)
    : patterns_(std::move(patterns)), match_distance_(match_distance) {}

void MeasuredRateCounter::add(const FrameRecord& truth, const CameraModel& camera,
                              const std::vector<RobotDetection>& detections,
                              const std::vector<MarkerRegionCentre>& marker_regions, int camera_id,
                              const std::vector<RejectedRobotCandidate>& rejected) {
  for (const RobotRecord& robot : truth.robots) {
    if (!robot.visible.value_or(false)) continue;
    // Shown by this camera: all its markers in the image (the truth's `visible` may be
    // another camera's).
    if (!camera.allInImage(
            markerOutlinePoints(patterns_, robot.team, robot.id, robot.x, robot.y, robot.theta)))
      continue;
    const auto top =
        projectDisc(camera, {robot.x, robot.y, patterns_.height(robot.team)}, patterns_.robot_radius);
    if (!top) continue;
    const Eigen::Vector2d& pixel = top->centre;
    const double radius_px = top->radius;
    MeasuredRate& own = by_robot_[{robot.team, robot.id}];
    // Each outcome counts in the total and in the robot's own counts.
    const auto count = [&](std::int64_t MeasuredRate::*field) {
      ++(total_.*field);
      ++(own.*field);
    };
    count(&MeasuredRate::visible);

    bool measured = false, near = false;
    for (const RobotDetection& d : detections) {
      if (std::hypot(d.x - robot.x, d.y - robot.y) > match_distance_) continue;
      near = true;
      measured = measured || (d.team == robot.team && d.id == robot.id);
    }
    if (measured) {
      count(&MeasuredRate::measured);
      continue;
    }
    const auto miss = [&](std::int64_t MeasuredRate::*field, const char* cause, const char* rejection = "") {
      count(field);
      misses_.push_back({truth.stamp, camera_id, robot.team, robot.id, cause, rejection, pixel});
    };
    if (near) {
      miss(&MeasuredRate::wrong_id, "wrong_id");
      continue;
    }
    bool segmented = false, team_region = false;
    for (const MarkerRegionCentre& r : marker_regions) {
      if ((r.pixel - pixel).norm() > radius_px) continue;
      segmented = true;
      team_region = team_region || r.team;
    }
    if (segmented) {
      // The rejected team region nearest the top's centre, on the top.
      const RejectedRobotCandidate* why = nullptr;
      double nearest = radius_px;
      for (const RejectedRobotCandidate& r : rejected) {
        const double d = std::hypot(r.u - pixel.x(), r.v - pixel.y());
        if (d <= nearest) nearest = d, why = &r;
      }
      if (why) {
        total_.rejected_by_cause.add(why->cause);
        own.rejected_by_cause.add(why->cause);
        miss(&MeasuredRate::identification_rejected, "identification_rejected",
             rejectionCauseName(why->cause));
      } else if (team_region) {
        count(&MeasuredRate::team_region_used);
        miss(&MeasuredRate::identification_rejected, "identification_rejected", kTeamRegionUsed);
      } else {
        count(&MeasuredRate::no_team_region);
        miss(&MeasuredRate::identification_rejected, "identification_rejected", kNoTeamRegion);
      }
    } else
      miss(&MeasuredRate::nothing_segmented, "nothing_segmented");
  }
}

}  // namespace soccer_vision
