#include "soccer_vision/identification/frame_identification.h"

namespace soccer_vision {

FrameIdentifier::FrameIdentifier(const CameraModel& camera, const PatternSet& patterns,
                                 const FieldGeometry& field, const IdentificationParams& params)
    : params_(params),
      robots_(camera, patterns, params.robots),
      balls_(camera, field, params.balls, RobotTop::of(patterns)) {}

void FrameIdentifier::setParams(const IdentificationParams& params) {
  params_ = params;
  robots_.setParams(params.robots);
  balls_.setParams(params.balls);
}

CameraFrameDetections FrameIdentifier::identify(const std::vector<Region>& regions, double stamp,
                                                int camera_id, bool global_search,
                                                std::vector<int>* confirmed, RecentIdentities* recent) const {
  CameraFrameDetections out;
  out.stamp = stamp;
  out.camera_id = camera_id;
  out.global_search = global_search;
  RobotIdentificationResult robots = robots_.identify(regions, recent, stamp);
  out.robots = std::move(robots.robots);
  out.rejections = robots.rejections;
  out.recalled_ids = robots.recalled_ids;
  out.small_marker_robots = robots.small_marker_robots;
  out.rejected_robots = std::move(robots.rejected);
  out.balls = balls_.detect(regions, robots.region_used, &out.rejections, out.robots);
  if (confirmed) {
    confirmed->clear();
    for (std::size_t r = 0; r < robots.region_confidence.size(); ++r) {
      if (robots.region_confidence[r] >= params_.confirm_confidence)
        confirmed->push_back(static_cast<int>(r));
    }
  }
  return out;
}

}  // namespace soccer_vision
