#include "frame_json.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "soccer_vision/segmentation/region_moments.h"

namespace soccer_vision {

namespace {

using nlohmann::json;

json nullable(bool valid, double value) { return valid ? json(value) : json(nullptr); }

// [mm] the larger axis-aligned std-dev of a position covariance [m²].
double sdMm(const Eigen::Matrix2d& covariance) {
  return 1e3 * std::sqrt(std::max({covariance(0, 0), covariance(1, 1), 0.0}));
}

json trackedJson(const TrackerOutput& out, double stamp, bool with_uncertainty) {
  json robots = json::array(), balls = json::array();
  for (const TrackedRobot& r : out.robots) {
    json j = {{"track", r.track_id},
              {"team", std::string(teamName(r.team))},
              {"id", r.id},
              {"x", r.x},
              {"y", r.y},
              {"theta", nullable(r.heading_valid, r.theta)},
              {"visible", r.visible}};
    if (with_uncertainty) {
      j["sd_mm"] = sdMm(r.position_covariance);
      j["unseen_s"] = stamp - r.last_measured;
    }
    robots.push_back(std::move(j));
  }
  for (const TrackedBall& b : out.balls) {
    json j = {{"track", b.track_id},
              {"x", b.x},
              {"y", b.y},
              {"vx", b.vx},
              {"vy", b.vy},
              {"z", b.z},
              {"visible", b.visible},
              {"primary", b.primary}};
    if (with_uncertainty) {
      j["sd_mm"] = sdMm(b.position_covariance);
      j["unseen_s"] = stamp - b.last_measured;
    }
    balls.push_back(std::move(j));
  }
  return {{"robots", robots}, {"balls", balls}};
}

}  // namespace

json regionsJson(const std::vector<Region>& regions) {
  json out = json::array();
  for (const Region& r : regions) {
    const PrincipalDeviations sd = principalDeviations(r.mu20, r.mu11, r.mu02);
    out.push_back({{"color", std::string(colorClassName(r.color))},
                   {"area", r.area},
                   {"cx", r.cx},
                   {"cy", r.cy},
                   {"box", {r.bbox.x, r.bbox.y, r.bbox.width, r.bbox.height}},
                   {"sd", {sd.major, sd.minor}},
                   {"angle", majorAxisAngle(r.mu20, r.mu11, r.mu02)}});
  }
  return out;
}

json detectionsJson(const CameraFrameDetections& d, bool placed) {
  json robots = json::array(), balls = json::array(), rejected = json::array(), causes = json::object();
  for (const RobotDetection& r : d.robots) {
    robots.push_back({{"team", std::string(teamName(r.team))},
                      {"id", r.id},
                      {"x", nullable(placed, r.x)},
                      {"y", nullable(placed, r.y)},
                      {"theta", nullable(placed && r.heading_valid, r.theta)},
                      {"u", r.pixel.x()},
                      {"v", r.pixel.y()},
                      {"confidence", r.confidence}});
  }
  for (const BallDetection& b : d.balls) {
    balls.push_back({{"x", nullable(placed, b.x)},
                     {"y", nullable(placed, b.y)},
                     {"u", b.pixel.x()},
                     {"v", b.pixel.y()},
                     {"area", b.area_px},
                     {"confidence", b.confidence}});
  }
  for (const auto& [name, count] : d.rejections.named(false)) causes[name] = count;
  for (const RejectedRobotCandidate& r : d.rejected_robots)
    rejected.push_back({{"u", r.u}, {"v", r.v}, {"cause", rejectionCauseName(r.cause)}});
  return {{"robots", robots}, {"balls", balls}, {"rejections", causes}, {"rejected_robots", rejected}};
}

json frameTraceJson(const PipelineFrame& f, const Tracker& tracker) {
  return {{"stamp", f.stamp},
          {"camera", f.camera_id},
          {"search", f.global_search ? "global" : "windows"},
          {"search_reason", globalSearchReasonName(f.search_reason)},
          {"rectangles", f.windows},
          {"tracker_reset", f.tracker_reset},
          {"regions", regionsJson(f.regions)},
          {"detections", detectionsJson(f.detections)},
          {"output", trackedJson(f.output, f.stamp, false)},
          {"tracks", trackedJson(tracker.predictions(f.stamp), f.stamp, true)}};
}

}  // namespace soccer_vision
