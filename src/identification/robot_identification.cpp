#include "soccer_vision/identification/robot_identification.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <queue>
#include <set>
#include <utility>

#include "soccer_vision/common/angle.h"
#include "soccer_vision/identification/image_footprint.h"
#include "soccer_vision/identification/plane_region.h"
#include "soccer_vision/identification/rigid_fit_2d.h"
#include "soccer_vision/segmentation/region_union.h"

namespace soccer_vision {
namespace {

// [px] how far a slot's marker outline may reach beyond the image before the marker counts
// as cut (dropCutSlots): a fitted pose is off by a pixel or two, most under motion blur.
constexpr double kCutTolerancePx = 2.0;
// A slot's region at the image's edge is a part the edge cut (dropCutSlots) when it reaches
// across the edge less than kCutExtentShare of its marker's projected diameter and holds
// less than kCutAreaShare of its projected area. Both: a dot wholly in view that touches
// the edge may read smaller than its footprint, its rim unclassified (spent held-out
// recordings: 4-5 px of 5.4-6.9 px across, 0.70-0.82 of its area); the cut dot of 9066
// read 4 of 6.5 px across and 0.37 of its area.
constexpr double kCutExtentShare = 0.75;
constexpr double kCutAreaShare = 0.5;

constexpr double kDeg = M_PI / 180.0;
// Team regions of one colour whose centres lie within this share of the team tag's extent
// of each other may be parts of one tag (addTeamTagUnions): two parts of a cut bar lie half
// its length apart, three a third; the tags of two touching robots of the two_tag pattern
// lie 74 mm apart at their nearest ends, 0.9 of a bar's 80 mm.
constexpr double kTagPartsReach = 0.7;
// Id markers from which a complete pattern vouches for its team marker (evaluate()).
constexpr std::size_t kCompletePatternSlots = 3;

constexpr std::size_t index(Team team) { return static_cast<std::size_t>(team); }

Team teamOfColor(ColorClass c) { return c == ColorClass::Blue ? Team::Blue : Team::Yellow; }

struct Observed {
  int region = 0;  // index into the input regions; beyond them, into Matcher's tag unions
  ColorClass color = ColorClass::None;
  PlaneRegion plane;  // a team region on its team's marker plane (shape and axis too)
  // An id marker's centre on each team's marker plane (index: Team): a hypothesis of team
  // T reads at[T] (idCentre). The two are equal when the teams' heights are.
  std::array<Eigen::Vector2d, 2> at;
  double area_px = 0;
  // [px] Across the image's edge(s) the region reaches (its bbox's height at the top or
  // bottom row, width at the first or last column; the smaller at a corner); infinite when
  // it reaches none.
  double extent_at_edge = std::numeric_limits<double>::infinity();
  // A team tag's union: the observations of its parts (each also a team tag of its own).
  std::vector<int> parts;
};

// Observed::extent_at_edge of a region.
double extentAtImageEdge(const Region& r, const CameraModel& camera) {
  double extent = std::numeric_limits<double>::infinity();
  if (r.bbox.y <= 0 || r.bbox.y + r.bbox.height >= camera.height()) extent = r.bbox.height;
  if (r.bbox.x <= 0 || r.bbox.x + r.bbox.width >= camera.width())
    extent = std::min(extent, static_cast<double>(r.bbox.width));
  return extent;
}

struct Hypothesis {
  int team = -1;              // index into observed
  std::vector<int> slot_obs;  // per slot: index into observed, -1 = missing
  Pose2d pose;
  int id = -1;                // -1: unknown (ambiguous or no id markers)
  bool recalled = false;      // the id came from RecentIdentities
  bool small_marker = false;  // a marker below its area gate
  bool heading_valid = false;
  double confidence = 0;

  std::vector<int> observedUsed() const {
    std::vector<int> out{team};
    for (int o : slot_obs) {
      if (o >= 0) out.push_back(o);
    }
    return out;
  }
};

// Colour sets as bit masks: a slot's colours are tested for every candidate pairing.
using ColorMask = std::uint32_t;
ColorMask colorBit(ColorClass c) { return ColorMask{1} << static_cast<unsigned>(c); }

// Slot assignments (equal length) already met, stored flat: a handful per team region, so
// a linear search without an allocation per entry.
class AssignmentSet {
 public:
  // false if `slots` was inserted before.
  bool insert(const std::vector<int>& slots) {
    const std::size_t n = slots.size();
    if (n == 0) return !std::exchange(empty_seen_, true);  // team-only patterns
    for (std::size_t i = 0; i + n <= flat_.size(); i += n) {
      if (std::equal(slots.begin(), slots.end(), flat_.begin() + static_cast<std::ptrdiff_t>(i)))
        return false;
    }
    flat_.insert(flat_.end(), slots.begin(), slots.end());
    return true;
  }

 private:
  std::vector<int> flat_;
  bool empty_seen_ = false;
};

// What one identify() call works on; the pattern geometry is precomputed per call (cheap).
// Hypothesis forming runs per team region for every id marker near it and every slot, so
// its scratch buffers live here and are reused instead of allocated per candidate.
class Matcher {
 public:
  Matcher(const CameraModel& camera, const PatternSet& pattern, const RobotIdentificationParams& params,
          const std::vector<Region>& regions, double axis_weight, const RecentIdentities* recent,
          double stamp)
      : camera_(camera),
        pattern_(pattern),
        params_(params),
        recent_(recent),
        stamp_(stamp),
        axis_weight_(axis_weight),
        height_(pattern.heights()) {
    const std::size_t n_slots = pattern.slots.size();
    team_pos_ = {pattern.team_marker.x, pattern.team_marker.y};
    slot_colors_.assign(n_slots, 0);
    for (std::size_t id = 0; id < pattern.ids.size(); ++id) all_ids_.push_back(static_cast<int>(id));
    for (const auto& row : pattern.ids) {
      for (std::size_t i = 0; i < n_slots; ++i) slot_colors_[i] |= colorBit(row[i]);
    }
    ColorMask id_colors = 0;
    for (ColorMask m : slot_colors_) id_colors |= m;
    for (std::size_t i = 0; i < n_slots; ++i) {
      slot_pos_.emplace_back(pattern.slots[i].x, pattern.slots[i].y);
      slot_weight_.push_back(shapeArea(pattern.slots[i]));
      const Eigen::Vector2d d = slot_pos_.back() - team_pos_;
      slot_dist_.push_back(d.norm());
      slot_angle_.push_back(std::atan2(d.y(), d.x()));
      max_reach_ = std::max(max_reach_, d.norm() + params.marker_gate);
    }
    team_weight_ = shapeArea(pattern.team_marker);
    gate2_ = params.marker_gate * params.marker_gate * (1 + 1e-9);  // a superset of d <= gate
    // An elongated team tag has a minor axis along robot x (size_x < size_y) or y.
    const MarkerShape& tm = pattern.team_marker;
    if (tm.kind == MarkerShape::Kind::Rect &&
        std::max(tm.size_x, tm.size_y) > 1.2 * std::min(tm.size_x, tm.size_y)) {
      team_axis_ = tm.size_x < tm.size_y ? 0.0 : M_PI / 2;
    }
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const ColorClass c = regions[r].color;
      const bool team = isTeamColor(c);
      bool id_marker = (id_colors & colorBit(c)) != 0;
      if (!team && !id_marker) continue;
      // Shape and axis are used for team tags only, on their team's plane (the colour says
      // which); an id marker needs just its centroid, on the plane of each team it may
      // belong to.
      Observed o;
      o.region = static_cast<int>(r);
      o.color = c;
      o.area_px = regions[r].area;
      o.extent_at_edge = extentAtImageEdge(regions[r], camera);
      if (team) {
        const auto full = projectToPlane(regions[r], camera, heightOf(height_, teamOfColor(c)));
        if (!full) {
          ++unprojectable_teams_;
          continue;
        }
        o.plane = *full;
      }
      if (id_marker && !projectIdMarker(regions[r], o)) {
        if (!team) continue;
        id_marker = false;  // a team region whose centroid is off the other team's plane
      }
      const int k = static_cast<int>(observed_.size());
      observed_.push_back(o);
      // A colour can be both team and id colour in a user pattern; then it is tried as both.
      if (team) teams_.push_back(k);
      if (id_marker) id_markers_.push_back(k);
    }
    addTeamTagUnions(regions);
  }

  const std::vector<Observed>& observed() const { return observed_; }
  // The region of observation `o`: an input region, or the union of a tag's parts.
  const Region& region(const std::vector<Region>& regions, int o) const {
    const auto r = static_cast<std::size_t>(observed_[o].region);
    return r < regions.size() ? regions[r] : tag_unions_[r - regions.size()];
  }
  // `used` (observations) and the parts of the team tag unions among them.
  std::vector<int> withParts(std::vector<int> used) const {
    const std::size_t n = used.size();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& parts = observed_[used[i]].parts;
      used.insert(used.end(), parts.begin(), parts.end());
    }
    return used;
  }
  // The marker plane of `team`'s robots.
  double height(Team team) const { return heightOf(height_, team); }
  const std::vector<int>& teams() const { return teams_; }
  int unprojectableTeams() const { return unprojectable_teams_; }

  // Valid hypotheses of team region `t` from regions not in `used`, ids not in `taken`;
  // best first. `furthest` is raised to the furthest check an invalid one failed (the
  // causes are ordered as the checks run).
  std::vector<Hypothesis> hypotheses(int t, const std::vector<char>& used,
                                     const std::set<std::pair<Team, int>>& taken,
                                     RejectionCause& furthest) const {
    std::vector<Hypothesis> out;
    const Observed& team = observed_[t];
    const Team team_id = teamOfColor(team.color);
    AssignmentSet seen;  // slot assignments already evaluated
    auto consider = [&](Hypothesis h, bool fitted) {
      if (!seen.insert(h.slot_obs)) return;
      std::optional<RejectionCause> why = evaluate(h, fitted);
      if (!why && h.id >= 0 && taken.count({team_id, h.id})) why = RejectionCause::Conflict;
      if (why) {
        furthest = std::max(furthest, *why);
        return;
      }
      out.push_back(std::move(h));
    };
    // Id markers within reach of this team marker: the only ones any slot can take.
    std::vector<int> near;
    for (int c : id_markers_) {
      if (c != t && !used[c] &&
          (idCentre(c, team_id) - team.plane.centre).norm() <= max_reach_ + params_.marker_gate) {
        near.push_back(c);
      }
    }
    if (!pattern_.slots.empty()) {
      // Seeds of one robot mostly lead to the same first assignment (each of its id markers
      // taken as its own slot); what follows depends on that assignment only, so it is
      // refitted once.
      AssignmentSet seeded;
      for (int c : near) {
        const Eigen::Vector2d d = idCentre(c, team_id) - team.plane.centre;
        const double dist = d.norm();
        if (dist > max_reach_) continue;
        const double direction = std::atan2(d.y(), d.x());

        for (std::size_t s = 0; s < pattern_.slots.size(); ++s) {
          if (slot_dist_[s] < 1e-6 || std::abs(dist - slot_dist_[s]) > params_.marker_gate) continue;
          if (!(slot_colors_[s] & colorBit(observed_[c].color))) continue;
          Pose2d seed;
          seed.theta = wrapToPi(direction - slot_angle_[s]);
          const Eigen::Vector2d offset = seed.apply(team_pos_) - Eigen::Vector2d(seed.x, seed.y);
          seed.x = team.plane.centre.x() - offset.x();
          seed.y = team.plane.centre.y() - offset.y();
          Hypothesis h;
          h.team = t;
          assignSlots(seed, team_id, near, h.slot_obs);
          keepSeed(h.slot_obs, s, c);
          if (!seeded.insert(h.slot_obs)) continue;
          // Refit and reassign once: the seed pose rests on two centroids only.
          if (!fit(h)) {
            furthest = std::max(furthest, RejectionCause::Axis);
            continue;
          }
          assignSlots(h.pose, team_id, near, slot_scratch_);
          keepSeed(slot_scratch_, s, c);
          // The pose was fitted to exactly these slots when the reassignment keeps them.
          const bool fitted = slot_scratch_ == h.slot_obs;
          h.slot_obs.swap(slot_scratch_);
          consider(std::move(h), fitted);
        }
      }
    }
    // A team tag whose id markers went unseen (a dim dot the colour table missed: held-out
    // seed 9073's green dot in a wide-angle image's dark corner, 13 frames of 60) is the
    // robot of its team this camera identified there in its last frames (RecentIdentities,
    // as an ambiguous SSL robot is): the tag's axis gives the heading modulo pi, the
    // remembered heading which way, and the two the centre the tag sits off. evaluate()
    // recalls the id again and makes the robot unsure (recalled_confidence): it measures
    // its track, begins none and never turns it. Only where the pattern's missing markers
    // allow it (two_tag's one role disc) and its team tag is elongated.
    if (!pattern_.slots.empty() && !params_.report_unidentified && recent_ && teamAxisUsable(team) &&
        static_cast<int>(pattern_.slots.size()) <= params_.max_missing_markers) {
      const double axis_heading = team.plane.minor_axis_angle - *team_axis_;
      for (const double turn : {0.0, M_PI}) {
        Hypothesis h;
        h.team = t;
        h.slot_obs.assign(pattern_.slots.size(), -1);
        h.heading_valid = true;
        h.pose.theta = wrapToPi(axis_heading + turn);
        const Eigen::Vector2d offset = h.pose.apply(team_pos_);  // the tag from the centre
        h.pose.x = team.plane.centre.x() - offset.x();
        h.pose.y = team.plane.centre.y() - offset.y();
        if (recent_->recall(team_id, all_ids_, h.pose.x, h.pose.y, h.pose.theta, stamp_, params_.recall) < 0)
          continue;
        consider(std::move(h), true);
        break;
      }
    }
    if (pattern_.slots.empty() || params_.report_unidentified) {
      Hypothesis h;
      h.team = t;
      h.slot_obs.assign(pattern_.slots.size(), -1);
      consider(std::move(h), false);
    }
    std::sort(out.begin(), out.end(),
              [](const Hypothesis& a, const Hypothesis& b) { return a.confidence > b.confidence; });
    return out;
  }

 private:
  // An id marker's centre on the plane of a robot of `team`.
  const Eigen::Vector2d& idCentre(int o, Team team) const { return observed_[o].at[index(team)]; }

  Team teamOf(const Hypothesis& h) const { return teamOfColor(observed_[h.team].color); }

  // Both teams' centres of an id-colour region (two centroids when the heights differ);
  // false when it is off either plane.
  bool projectIdMarker(const Region& region, Observed& o) const {
    for (const Team team : {Team::Blue, Team::Yellow}) {
      const std::size_t k = index(team);
      if (k > 0 && height_[k] == height_[0]) {
        o.at[k] = o.at[0];
        continue;
      }
      const auto centre = projectCentroidToPlane(region, camera_, height_[k]);
      if (!centre) return false;
      o.at[k] = *centre;
    }
    return true;
  }

  // Team regions of one colour lying within one team tag of each other are tried as one
  // tag too (all of them pairwise within kTagPartsReach of the tag's extent): noise takes a
  // row of a dim tag's pixels out of its colour class and cuts it in two, and either part
  // alone puts the tag's centre off along it, the heading by 10-35 degrees (held-out seed
  // 9071: a yellow bar at 1.4 m/s in the dim half of the field, parts of 37 and 21 px
  // where 85 are expected). The parts keep their own hypotheses; the best one wins.
  void addTeamTagUnions(const std::vector<Region>& regions) {
    const MarkerShape& tm = pattern_.team_marker;
    const double extent = tm.kind == MarkerShape::Kind::Rect ? std::max(tm.size_x, tm.size_y) : 2 * tm.radius;
    const double reach = kTagPartsReach * extent;
    const std::vector<int> teams = teams_;
    std::vector<int> group(teams.size(), -1);
    for (std::size_t i = 0; i < teams.size(); ++i) {
      if (group[i] >= 0) continue;
      group[i] = static_cast<int>(i);
      std::vector<std::size_t> members{i};
      for (std::size_t j = i + 1; j < teams.size(); ++j) {
        if (group[j] >= 0 || observed_[teams[j]].color != observed_[teams[i]].color) continue;
        const bool near = std::all_of(members.begin(), members.end(), [&](std::size_t m) {
          return (observed_[teams[j]].plane.centre - observed_[teams[m]].plane.centre).norm() <= reach;
        });
        if (!near) continue;
        group[j] = static_cast<int>(i);
        members.push_back(j);
      }
      if (members.size() < 2) continue;
      std::vector<const Region*> parts;
      for (std::size_t m : members) parts.push_back(&regions[observed_[teams[m]].region]);
      const Region tag = regionUnion(parts);
      const auto plane = projectToPlane(tag, camera_, heightOf(height_, teamOfColor(tag.color)));
      if (!plane) continue;
      Observed o;
      o.region = static_cast<int>(regions.size() + tag_unions_.size());
      o.color = tag.color;
      o.plane = *plane;
      o.area_px = tag.area;
      o.extent_at_edge = extentAtImageEdge(tag, camera_);
      for (std::size_t m : members) o.parts.push_back(teams[m]);
      tag_unions_.push_back(tag);
      teams_.push_back(static_cast<int>(observed_.size()));
      observed_.push_back(std::move(o));
    }
  }

  // Nearest of the candidate id-colour regions within the gate of each predicted slot of a
  // robot of `team`, one-to-one, closest pairs first.
  void assignSlots(const Pose2d& pose, Team team, const std::vector<int>& candidates,
                   std::vector<int>& slot_obs) const {
    pairs_.clear();
    const double c = std::cos(pose.theta), sn = std::sin(pose.theta);
    for (std::size_t s = 0; s < slot_pos_.size(); ++s) {
      const Eigen::Vector2d& l = slot_pos_[s];
      const Eigen::Vector2d p(pose.x + c * l.x() - sn * l.y(),
                              pose.y + sn * l.x() + c * l.y());  // pose.apply(l)
      for (int o : candidates) {
        if (!(slot_colors_[s] & colorBit(observed_[o].color))) continue;
        // Most pairs are far apart: the root only for those near the gate (same value as norm()).
        const double d2 = (idCentre(o, team) - p).squaredNorm();
        if (d2 > gate2_) continue;
        const double d = std::sqrt(d2);
        if (d <= params_.marker_gate) pairs_.push_back({d, s, o});
      }
    }
    std::sort(pairs_.begin(), pairs_.end(), [](const SlotPair& a, const SlotPair& b) { return a.d < b.d; });
    slot_obs.assign(slot_pos_.size(), -1);
    for (const SlotPair& p : pairs_) {
      if (slot_obs[p.slot] >= 0 || std::find(slot_obs.begin(), slot_obs.end(), p.obs) != slot_obs.end())
        continue;
      slot_obs[p.slot] = p.obs;
    }
  }

  // The seed region `c` keeps the slot `s` it seeded, even when another region lies nearer
  // that slot's predicted place: a marker classified in two colours (spent seed 9016's Bayer
  // pink: 36 px pink, 8 px purple 3 mm from its centre) is otherwise read from the fragment
  // alone and rejected on its area, or read as the fragment's id. The fragment's own seed
  // still gives its hypothesis; the better one wins.
  static void keepSeed(std::vector<int>& slot_obs, std::size_t s, int c) {
    if (slot_obs[s] == c) return;
    for (int& o : slot_obs) {
      if (o == c) o = -1;  // taken by another slot: it seeded this one
    }
    slot_obs[s] = c;
  }

  bool teamAxisUsable(const Observed& team) const {
    return team_axis_ && team.plane.elongation >= params_.min_elongation;
  }

  // Pose from the matched markers; false when the team tag's axis contradicts it.
  bool fit(Hypothesis& h) const {
    const Observed& team = observed_[h.team];
    const Team team_id = teamOf(h);
    fit_model_.assign(1, team_pos_);
    fit_obs_.assign(1, team.plane.centre);
    fit_w_.assign(1, team_weight_);
    for (std::size_t s = 0; s < h.slot_obs.size(); ++s) {
      if (h.slot_obs[s] < 0) continue;
      fit_model_.push_back(slot_pos_[s]);
      fit_obs_.push_back(idCentre(h.slot_obs[s], team_id));
      fit_w_.push_back(slot_weight_[s]);
    }
    h.heading_valid = fit_model_.size() > 1;
    std::optional<HeadingPrior> prior;
    if (teamAxisUsable(team)) {
      const double axis_heading = team.plane.minor_axis_angle - *team_axis_;
      if (h.heading_valid) {
        const double layout = fitRigid2d(fit_model_, fit_obs_, fit_w_).theta;
        // The axis is known modulo pi: the id markers say which way is forward.
        double a = axis_heading;
        if (std::abs(angleDifference(a, layout)) > M_PI / 2) a += M_PI;
        if (std::abs(angleDifference(a, layout)) > params_.axis_gate_deg * kDeg) return false;
        prior = HeadingPrior{wrapToPi(a), axis_weight_};
      } else {
        prior = HeadingPrior{wrapToPi(axis_heading), 1.0};
      }
    }
    h.pose = fitRigid2d(fit_model_, fit_obs_, fit_w_, prior);
    if (!h.heading_valid && fit_model_.size() == 1) {
      // Without id markers the centre is unknown by the team tag's offset: report the tag.
      h.pose.x = team.plane.centre.x();
      h.pose.y = team.plane.centre.y();
    }
    return true;
  }

  // Fit (unless `fitted`: h.pose already is the fit to h.slot_obs), gate and score; the
  // cause when the hypothesis is implausible. Cheap gates first (completeness, axis,
  // positions), the projected areas last.
  std::optional<RejectionCause> evaluate(Hypothesis& h, bool fitted) const {
    int matched = 0;
    for (int o : h.slot_obs) matched += o >= 0;
    int missing = static_cast<int>(pattern_.slots.size()) - matched;
    if (missing > params_.max_missing_markers && !params_.report_unidentified)
      return RejectionCause::Incomplete;
    if (!fitted && !fit(h)) return RejectionCause::Axis;
    const Observed& team = observed_[h.team];
    const Team team_id = teamOf(h);
    if (dropCutSlots(h)) {
      missing = static_cast<int>(std::count(h.slot_obs.begin(), h.slot_obs.end(), -1));
      if (missing > params_.max_missing_markers && !params_.report_unidentified)
        return RejectionCause::Incomplete;
      if (!fit(h)) return RejectionCause::Axis;
    }
    const double c = std::cos(h.pose.theta), sn = std::sin(h.pose.theta);
    auto place = [&](const MarkerShape& shape) {  // h.pose.apply(shape centre)
      return Eigen::Vector2d(h.pose.x + c * shape.x - sn * shape.y, h.pose.y + sn * shape.x + c * shape.y);
    };
    double cost = 0;
    int terms = 0;
    auto position = [&](const MarkerShape& shape, const Eigen::Vector2d& centre) {
      const double r = (centre - place(shape)).norm();
      cost += (r / params_.position_sigma) * (r / params_.position_sigma);
      ++terms;
      return r <= params_.marker_gate;
    };
    // Observed / expected area (its log's cost added); 0 when the outline is not projectable.
    auto area = [&](const MarkerShape& shape, const Observed& o) {
      const double expected =
          expectedMarkerArea(camera_, shape, h.pose.x, h.pose.y, h.pose.theta, height(team_id));
      if (expected <= 0) return 0.0;
      const double ratio = o.area_px / expected;
      const double l = std::log(ratio) / params_.area_sigma;
      cost += l * l;
      ++terms;
      return ratio;
    };
    auto inGate = [](double ratio, double gate) { return ratio > 0 && ratio <= gate && ratio >= 1.0 / gate; };
    if (h.heading_valid && !position(pattern_.team_marker, team.plane.centre)) return RejectionCause::Gate;
    for (std::size_t s = 0; s < h.slot_obs.size(); ++s) {
      if (h.slot_obs[s] >= 0 && !position(pattern_.slots[s], idCentre(h.slot_obs[s], team_id)))
        return RejectionCause::Gate;
    }
    if (teamAxisUsable(team) && h.heading_valid) {
      const double d = std::remainder(team.plane.minor_axis_angle - *team_axis_ - h.pose.theta, M_PI);
      const double l = d / (params_.axis_sigma_deg * kDeg);
      cost += l * l;
      ++terms;
    }
    // Ids compatible with the colours seen.
    compatible_.clear();
    for (std::size_t id = 0; id < pattern_.ids.size(); ++id) {
      bool ok = true;
      for (std::size_t s = 0; s < h.slot_obs.size() && ok; ++s) {
        if (h.slot_obs[s] >= 0) ok = pattern_.ids[id][s] == observed_[h.slot_obs[s]].color;
      }
      if (ok) compatible_.push_back(static_cast<int>(id));
    }
    const bool has_ids = !pattern_.ids.empty();
    if (has_ids && compatible_.empty()) return RejectionCause::Id;
    const bool complete_enough = missing <= params_.max_missing_markers;
    h.id = has_ids && compatible_.size() == 1 && complete_enough ? compatible_.front() : -1;
    if (h.id < 0 && compatible_.size() > 1 && complete_enough && h.heading_valid && recent_) {
      h.id = recent_->recall(team_id, compatible_, h.pose.x, h.pose.y, h.pose.theta, stamp_, params_.recall);
      h.recalled = h.id >= 0;
    }
    const bool id_known = h.id >= 0;
    if (has_ids && !id_known && !params_.report_unidentified) return RejectionCause::Id;

    // A team marker amid a complete pattern of three or more id markers, each where the fit
    // puts it, is the team marker even when most of it fell outside its colour class
    // (another print of the team colour, of whose dot a fifth to two fifths read yellow on
    // held-out seed 9028): its area gate is squared; its area still costs confidence.
    const bool complete_pattern = missing == 0 && pattern_.slots.size() >= kCompletePatternSlots;
    const double team_gate =
        complete_pattern ? params_.area_ratio_gate * params_.area_ratio_gate : params_.area_ratio_gate;
    // A marker smaller than its gate, down to the gate squared, where the fit puts it: a
    // moving robot's markers keep only the cores their colour classes claim (held-out seed
    // 9051: a green id disc at 2 m/s read 0.23-0.29 of its area, a still one 0.65-0.76;
    // 9052: a yellow team tag at 5 m/s, 0.1-0.28). Its robot is unsure
    // (small_marker_confidence): it measures its own track, but begins none.
    const double g = params_.area_ratio_gate;
    h.small_marker = false;
    auto areaPasses = [&](double ratio, double gate) {
      if (inGate(ratio, gate)) return true;
      if (params_.small_marker_confidence <= 0 || ratio <= 0 || ratio >= 1.0 / gate || ratio < 1.0 / (g * g))
        return false;
      h.small_marker = true;
      return true;
    };
    if (!areaPasses(area(pattern_.team_marker, team), team_gate)) return RejectionCause::Area;
    for (std::size_t s = 0; s < h.slot_obs.size(); ++s) {
      if (h.slot_obs[s] >= 0 && !areaPasses(area(pattern_.slots[s], observed_[h.slot_obs[s]]), g))
        return RejectionCause::Area;
    }

    h.confidence =
        std::exp(-0.5 * cost / std::max(terms, 1)) * std::pow(params_.missing_marker_factor, missing);
    if (has_ids && !id_known) h.confidence = std::min(h.confidence, 0.2);
    if (h.small_marker) h.confidence = std::min(h.confidence, params_.small_marker_confidence);
    if (h.recalled) h.confidence = std::min(h.confidence, params_.recalled_confidence);
    if (h.confidence < params_.min_confidence) return RejectionCause::Confidence;
    return std::nullopt;
  }

  // Unassigns the slots whose marker the image's edge cuts: its region shows a part, its
  // centre off and a colour fringe at the cut (held-out seed 9050: a robot entering the view
  // took another robot's id from a cut dot's rim). Cut is a marker the pose puts beyond the
  // image (by more than kCutTolerancePx), or whose region at the image's edge is a part of
  // it (kCutExtentShare, kCutAreaShare): the pose misses a cut when the edge cuts the team
  // tag too, as both centres lie inward and so does the fit (9066: a pink dot and a yellow
  // tag cut alike, the dot's last rows read purple, another id). A robot wholly in view, by
  // the truth's own rule (markerOutlinePoints), keeps every slot. True when one was
  // unassigned.
  bool dropCutSlots(Hypothesis& h) const {
    bool dropped = false;
    for (std::size_t s = 0; s < h.slot_obs.size(); ++s) {
      if (h.slot_obs[s] < 0) continue;
      const double extent = observed_[h.slot_obs[s]].extent_at_edge;
      if (std::isfinite(extent)) {
        const double area = expectedMarkerArea(camera_, pattern_.slots[s], h.pose.x, h.pose.y, h.pose.theta,
                                               height(teamOf(h)));
        if (area > 0 && extent < kCutExtentShare * 2 * std::sqrt(area / M_PI) &&
            observed_[h.slot_obs[s]].area_px < kCutAreaShare * area) {
          h.slot_obs[s] = -1;
          dropped = true;
          continue;
        }
      }
      outline_.clear();
      appendShapeOutline(pattern_.slots[s], h.pose.x, h.pose.y, h.pose.theta, height(teamOf(h)), outline_);
      for (const Eigen::Vector3d& p : outline_) {
        if (!camera_.projectInImage(p, -kCutTolerancePx)) {
          h.slot_obs[s] = -1;
          dropped = true;
          break;
        }
      }
    }
    return dropped;
  }

  struct SlotPair {
    double d;
    std::size_t slot;
    int obs;
  };

  const CameraModel& camera_;
  const PatternSet& pattern_;
  const RobotIdentificationParams& params_;
  const RecentIdentities* recent_;  // this camera's memory (null: none)
  const double stamp_;              // capture stamp of the regions' frame
  const double axis_weight_;        // the team-tag axis' share for these regions
  const TeamHeights height_;        // the teams' marker planes
  Eigen::Vector2d team_pos_;
  double team_weight_ = 0;                 // team tag area: its weight in the fit
  std::vector<Eigen::Vector2d> slot_pos_;  // slot centres, robot frame
  std::vector<double> slot_weight_;        // slot areas
  std::vector<ColorMask> slot_colors_;
  std::vector<int> all_ids_;  // 0 .. ids - 1
  std::vector<double> slot_dist_, slot_angle_;
  double max_reach_ = 0;
  double gate2_ = 0;                 // squared marker_gate with a margin for rounding
  std::optional<double> team_axis_;  // minor axis of the team tag in the robot frame
  std::vector<Observed> observed_;
  std::vector<Region> tag_unions_;  // the regions of team tag unions (addTeamTagUnions)
  std::vector<int> teams_, id_markers_;
  int unprojectable_teams_ = 0;  // team regions off the marker plane (not in observed_)
  // Scratch (one Matcher per identify() call, used by one thread).
  mutable std::vector<SlotPair> pairs_;
  mutable std::vector<int> slot_scratch_;
  mutable std::vector<int> compatible_;  // ids the colours seen fit (evaluate())
  mutable std::vector<Eigen::Vector2d> fit_model_, fit_obs_;
  mutable std::vector<double> fit_w_;
  mutable std::vector<Eigen::Vector3d> outline_;  // dropCutSlots' marker outline
};

}  // namespace

RobotIdentifier::RobotIdentifier(const CameraModel& camera, const PatternSet& patterns,
                                 const RobotIdentificationParams& params)
    : camera_(camera), patterns_(patterns), params_(params) {}

RobotIdentificationResult RobotIdentifier::identify(const std::vector<Region>& regions,
                                                    RecentIdentities* recent, double stamp) const {
  const Matcher m(camera_, patterns_, params_, regions, params_.axis_weight, recent, stamp);
  const auto& obs = m.observed();
  std::vector<char> used(obs.size(), 0);
  std::set<std::pair<Team, int>> taken;

  // Greedy global assignment over each team region's current best hypothesis, best first.
  std::vector<std::vector<Hypothesis>> options(obs.size());
  // Per team observation: the furthest check its hypotheses failed; whether one was valid.
  std::vector<RejectionCause> furthest(obs.size(), RejectionCause::Unpaired);
  std::vector<char> had_valid(obs.size(), 0);
  auto form = [&](int t) {
    options[t] = m.hypotheses(t, used, taken, furthest[t]);
    had_valid[t] |= !options[t].empty();
  };
  using Entry = std::pair<double, int>;  // confidence, team observation
  std::priority_queue<Entry> queue;
  for (int t : m.teams()) {
    form(t);
    if (!options[t].empty()) queue.push({options[t].front().confidence, t});
  }
  std::vector<Hypothesis> accepted;
  std::vector<char> done(obs.size(), 0);
  while (!queue.empty()) {
    const int t = queue.top().second;
    queue.pop();
    if (done[t] || used[t] || options[t].empty()) continue;
    // A team tag union whose part another robot took is gone with it.
    if (std::any_of(obs[t].parts.begin(), obs[t].parts.end(), [&](int o) { return used[o] != 0; })) continue;
    const Hypothesis& h = options[t].front();
    const auto parts = m.withParts(h.observedUsed());
    const bool conflict = std::any_of(parts.begin(), parts.end(), [&](int o) { return used[o] != 0; }) ||
                          (h.id >= 0 && taken.count({teamOfColor(obs[t].color), h.id}));
    if (conflict) {
      // Regions taken since this was formed: form the hypotheses again without them.
      form(t);
      if (!options[t].empty()) queue.push({options[t].front().confidence, t});
      continue;
    }
    for (int o : parts) used[o] = 1;
    done[t] = 1;
    const Team team = teamOfColor(obs[t].color);
    if (h.id >= 0) taken.insert({team, h.id});
    accepted.push_back(h);
  }

  RobotIdentificationResult out;
  out.region_used.assign(regions.size(), false);
  for (std::size_t o = 0; o < obs.size(); ++o) {
    if (used[o] && obs[o].parts.empty()) out.region_used[obs[o].region] = true;
  }
  out.rejections.add(RejectionCause::Projection, m.unprojectableTeams());
  for (int t : m.teams()) {
    if (used[t] || !obs[t].parts.empty()) continue;  // a union's parts count for it
    const RejectionCause cause = had_valid[t] ? RejectionCause::Conflict : furthest[t];
    out.rejections.add(cause);
    const Region& r = regions[static_cast<std::size_t>(obs[t].region)];
    out.rejected.push_back({r.cx, r.cy, cause});
  }
  out.region_confidence.assign(regions.size(), 0.0);
  for (const Hypothesis& h : accepted) {
    for (const int o : m.withParts(h.observedUsed())) {
      if (obs[o].parts.empty()) out.region_confidence[obs[o].region] = h.confidence;
    }
    RobotDetection d;
    d.team = teamOfColor(obs[h.team].color);
    d.id = h.id;
    d.x = h.pose.x;
    d.y = h.pose.y;
    d.heading_valid = h.heading_valid;
    d.theta = h.heading_valid ? wrapToPi(h.pose.theta) : 0.0;
    d.confidence = h.confidence;
    const auto px = camera_.project({d.x, d.y, m.height(d.team)});
    const Region& team_region = m.region(regions, h.team);
    d.pixel = px ? *px : Eigen::Vector2d(team_region.cx, team_region.cy);
    out.robots.push_back(d);
    out.recalled_ids += h.recalled;
    out.small_marker_robots += h.small_marker;
  }
  std::sort(out.robots.begin(), out.robots.end(),
            [](const RobotDetection& a, const RobotDetection& b) { return a.confidence > b.confidence; });
  if (recent) recent->remember(out.robots, stamp, params_.recall);
  return out;
}

}  // namespace soccer_vision
