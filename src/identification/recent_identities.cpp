#include "soccer_vision/identification/recent_identities.h"

#include <algorithm>
#include <cmath>

#include "soccer_vision/common/angle.h"

namespace soccer_vision {

int RecentIdentities::recall(Team team, const std::vector<int>& candidates, double x, double y, double theta,
                             double stamp, const RecallParams& params) const {
  if (params.max_age <= 0) return -1;
  const Entry* there = nullptr;
  for (const Entry& e : entries_) {
    const double age = stamp - e.stamp;
    if (e.team != team || !(age > 0) || age > params.max_age) continue;
    const double dx = x - (e.x + e.vx * age), dy = y - (e.y + e.vy * age);
    if (std::hypot(dx, dy) > params.max_distance) continue;
    if (there) return -1;  // two robots of the team there: neither is sure
    there = &e;
  }
  if (!there || std::find(candidates.begin(), candidates.end(), there->id) == candidates.end()) return -1;
  if (std::abs(angleDifference(theta, there->theta)) > params.max_heading_deg * M_PI / 180) return -1;
  return there->id;
}

void RecentIdentities::remember(const std::vector<RobotDetection>& robots, double stamp,
                                const RecallParams& params) {
  if (!std::isfinite(stamp)) return;
  if (stamp < last_stamp_) entries_.clear();
  last_stamp_ = stamp;
  for (const RobotDetection& r : robots) {
    if (r.id < 0 || !r.heading_valid || !std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.theta))
      continue;
    auto e = std::find_if(entries_.begin(), entries_.end(),
                          [&](const Entry& k) { return k.team == r.team && k.id == r.id; });
    const bool fresh = e == entries_.end();
    if (fresh) e = entries_.insert(entries_.end(), Entry{r.team, r.id});
    const double dt = stamp - e->stamp;
    if (!fresh && dt > 0 && dt <= params.max_age) {
      e->vx = (r.x - e->x) / dt;
      e->vy = (r.y - e->y) / dt;
    } else if (dt > 0) {  // first sighting, or after a gap: its motion is unknown
      e->vx = e->vy = 0;
    }
    e->x = r.x;
    e->y = r.y;
    e->theta = r.theta;
    e->stamp = stamp;
  }
}

}  // namespace soccer_vision
