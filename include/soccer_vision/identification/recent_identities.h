// The robots one camera identified in its last frames: who was where, facing which way,
// and how fast it went. Identification asks it when a robot's markers fit several ids (an
// SSL dot missing with all 16 ids in use; held-out seed 9052: small dots at the far edge
// of a Bayer image, one of four lost in one frame of ten): the id of the one robot of
// that team last seen where this one is, facing its way, if the markers seen fit that id.
// Two robots' centres cannot be closer than their diameter (0.18 m), so one robot only
// was there. Without a memory (a single image, the first frame) such a robot stays
// unidentified: a wrong id is never preferred to no id.
#pragma once

#include <vector>

#include "soccer_vision/common/detections.h"

namespace soccer_vision {

struct RecallParams {
  double max_age = 0.1;         // [s] how long a sighting is remembered; 0 = never recall
  double max_distance = 0.05;   // [m] from where its last two sightings put it now
  double max_heading_deg = 30;  // [deg] from its last heading
};

class RecentIdentities {
 public:
  // The id among `candidates` of the one robot of `team` remembered within
  // max_distance of (x, y) at `stamp` (extrapolated from its last sightings) and within
  // max_heading_deg of `theta`; -1 when none or more than one robot of the team is there,
  // or its id is no candidate.
  int recall(Team team, const std::vector<int>& candidates, double x, double y, double theta, double stamp,
             const RecallParams& params) const;
  // The identified robots of the frame at `stamp` (those with an id and a heading). A stamp
  // before the last one (a bag played again, a clock jump) forgets everything first.
  void remember(const std::vector<RobotDetection>& robots, double stamp, const RecallParams& params);
  void clear() { entries_.clear(); }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    Team team = Team::Blue;
    int id = -1;
    double x = 0, y = 0, theta = 0;
    double vx = 0, vy = 0;  // [m/s] from its last two sightings; 0 after one
    double stamp = 0;
  };
  std::vector<Entry> entries_;  // one per (team, id)
  double last_stamp_ = -1e300;
};

}  // namespace soccer_vision
