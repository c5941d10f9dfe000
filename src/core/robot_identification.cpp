#include "soccer_vision/robot_identification.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <queue>
#include <set>
#include <utility>

#include "soccer_vision/image_footprint.h"
#include "soccer_vision/plane_region.h"
#include "soccer_vision/rigid_fit_2d.h"

namespace soccer_vision {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Observed {
  int region = 0;  // index into the input regions
  ColorClass color = ColorClass::None;
  PlaneRegion plane;
  double area_px = 0;
};

struct Hypothesis {
  int team = -1;                 // index into observed
  std::vector<int> slot_obs;     // per slot: index into observed, -1 = missing
  Pose2d pose;
  int id = -1;                   // -1: unknown (ambiguous or no id markers)
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

// What one identify() call works on; the pattern geometry is precomputed per call (cheap).
class Matcher {
 public:
  Matcher(const CameraModel& camera, const PatternSet& pattern, const RobotIdentificationParams& params,
          const std::vector<Region>& regions)
      : camera_(camera), pattern_(pattern), params_(params) {
    const std::size_t n_slots = pattern.slots.size();
    team_pos_ = {pattern.team_marker.x, pattern.team_marker.y};
    slot_colors_.resize(n_slots);
    for (const auto& row : pattern.ids) {
      for (std::size_t i = 0; i < n_slots; ++i) slot_colors_[i].insert(row[i]);
    }
    for (std::size_t i = 0; i < n_slots; ++i) {
      const Eigen::Vector2d d = Eigen::Vector2d(pattern.slots[i].x, pattern.slots[i].y) - team_pos_;
      slot_dist_.push_back(d.norm());
      slot_angle_.push_back(std::atan2(d.y(), d.x()));
      max_reach_ = std::max(max_reach_, d.norm() + params.marker_gate);
    }
    // An elongated team tag has a minor axis along robot x (size_x < size_y) or y.
    const MarkerShape& tm = pattern.team_marker;
    if (tm.kind == MarkerShape::Kind::Rect && std::max(tm.size_x, tm.size_y) > 1.2 * std::min(tm.size_x, tm.size_y)) {
      team_axis_ = tm.size_x < tm.size_y ? 0.0 : M_PI / 2;
    }
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const ColorClass c = regions[r].color;
      const bool team = c == ColorClass::Blue || c == ColorClass::Yellow;
      const bool id_marker = std::any_of(slot_colors_.begin(), slot_colors_.end(),
                                         [c](const std::set<ColorClass>& s) { return s.count(c) > 0; });
      if (!team && !id_marker) continue;
      const auto plane = projectToPlane(regions[r], camera, pattern.robot_height);
      if (!plane) continue;
      const int o = static_cast<int>(observed_.size());
      observed_.push_back({static_cast<int>(r), c, *plane, static_cast<double>(regions[r].area)});
      // A colour can be both team and id colour in a user pattern; then it is tried as both.
      if (team) teams_.push_back(o);
      if (id_marker) id_markers_.push_back(o);
    }
  }

  const std::vector<Observed>& observed() const { return observed_; }
  const std::vector<int>& teams() const { return teams_; }

  // Valid hypotheses of team region `t` from regions not in `used`, ids not in `taken`;
  // best first.
  std::vector<Hypothesis> hypotheses(int t, const std::vector<char>& used,
                                     const std::set<std::pair<Team, int>>& taken) const {
    std::vector<Hypothesis> out;
    const Observed& team = observed_[t];
    const Team team_id = team.color == ColorClass::Blue ? Team::Blue : Team::Yellow;
    std::set<std::vector<int>> seen;
    auto consider = [&](Hypothesis h) {
      if (!seen.insert(h.slot_obs).second) return;
      if (!evaluate(h)) return;
      if (h.id >= 0 && taken.count({team_id, h.id})) return;
      out.push_back(std::move(h));
    };
    // Id markers within reach of this team marker: the only ones any slot can take.
    std::vector<int> near;
    for (int c : id_markers_) {
      if (c != t && !used[c] && (observed_[c].plane.centre - team.plane.centre).norm() <= max_reach_ + params_.marker_gate) {
        near.push_back(c);
      }
    }
    if (!pattern_.slots.empty()) {
      for (int c : near) {
        const Eigen::Vector2d d = observed_[c].plane.centre - team.plane.centre;
        const double dist = d.norm();
        if (dist > max_reach_) continue;

        for (std::size_t s = 0; s < pattern_.slots.size(); ++s) {
          if (slot_dist_[s] < 1e-6 || std::abs(dist - slot_dist_[s]) > params_.marker_gate) continue;
          if (!slot_colors_[s].count(observed_[c].color)) continue;
          Pose2d seed;
          seed.theta = wrapAngle(std::atan2(d.y(), d.x()) - slot_angle_[s]);
          const Eigen::Vector2d offset = seed.apply(team_pos_) - Eigen::Vector2d(seed.x, seed.y);
          seed.x = team.plane.centre.x() - offset.x();
          seed.y = team.plane.centre.y() - offset.y();
          Hypothesis h;
          h.team = t;
          h.slot_obs = assignSlots(seed, near);
          if (h.slot_obs[s] < 0) continue;  // the seed itself did not survive the assignment
          // Refit and reassign once: the seed pose rests on two centroids only.
          if (!fit(h)) continue;
          h.slot_obs = assignSlots(h.pose, near);
          consider(std::move(h));
        }
      }
    }
    if (pattern_.slots.empty() || params_.report_unidentified) {
      Hypothesis h;
      h.team = t;
      h.slot_obs.assign(pattern_.slots.size(), -1);
      consider(std::move(h));
    }
    std::sort(out.begin(), out.end(),
              [](const Hypothesis& a, const Hypothesis& b) { return a.confidence > b.confidence; });
    return out;
  }

 private:
  // Nearest of the candidate id-colour regions within the gate of each predicted slot,
  // one-to-one, closest pairs first.
  std::vector<int> assignSlots(const Pose2d& pose, const std::vector<int>& candidates) const {
    struct Pair {
      double d;
      std::size_t slot;
      int obs;
    };
    std::vector<Pair> pairs;
    for (std::size_t s = 0; s < pattern_.slots.size(); ++s) {
      const Eigen::Vector2d p = pose.apply({pattern_.slots[s].x, pattern_.slots[s].y});
      for (int c : candidates) {
        if (!slot_colors_[s].count(observed_[c].color)) continue;
        const double d = (observed_[c].plane.centre - p).norm();
        if (d <= params_.marker_gate) pairs.push_back({d, s, c});
      }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d < b.d; });
    std::vector<int> slot_obs(pattern_.slots.size(), -1);
    std::set<int> taken;
    for (const Pair& p : pairs) {
      if (slot_obs[p.slot] >= 0 || taken.count(p.obs)) continue;
      slot_obs[p.slot] = p.obs;
      taken.insert(p.obs);
    }
    return slot_obs;
  }

  bool teamAxisUsable(const Observed& team) const {
    return team_axis_ && team.plane.elongation >= params_.min_elongation;
  }

  // Pose from the matched markers; false when the team tag's axis contradicts it.
  bool fit(Hypothesis& h) const {
    const Observed& team = observed_[h.team];
    std::vector<Eigen::Vector2d> model{team_pos_}, obs{team.plane.centre};
    std::vector<double> w{shapeArea(pattern_.team_marker)};
    for (std::size_t s = 0; s < h.slot_obs.size(); ++s) {
      if (h.slot_obs[s] < 0) continue;
      model.emplace_back(pattern_.slots[s].x, pattern_.slots[s].y);
      obs.push_back(observed_[h.slot_obs[s]].plane.centre);
      w.push_back(shapeArea(pattern_.slots[s]));
    }
    h.heading_valid = model.size() > 1;
    std::optional<HeadingPrior> prior;
    if (teamAxisUsable(team)) {
      const double axis_heading = team.plane.minor_axis_angle - *team_axis_;
      if (h.heading_valid) {
        const double layout = fitRigid2d(model, obs, w).theta;
        // The axis is known modulo pi: the id markers say which way is forward.
        double a = axis_heading;
        if (std::abs(angleDifference(a, layout)) > M_PI / 2) a += M_PI;
        if (std::abs(angleDifference(a, layout)) > params_.axis_gate_deg * kDeg) return false;
        prior = HeadingPrior{wrapAngle(a), params_.axis_weight};
      } else {
        prior = HeadingPrior{wrapAngle(axis_heading), 1.0};
      }
    }
    h.pose = fitRigid2d(model, obs, w, prior);
    if (!h.heading_valid && model.size() == 1) {
      // Without id markers the centre is unknown by the team tag's offset: report the tag.
      h.pose.x = team.plane.centre.x();
      h.pose.y = team.plane.centre.y();
    }
    return true;
  }

  // Fit, gate and score; false when the hypothesis is implausible. Cheap gates first
  // (completeness, positions, axis), the projected areas last.
  bool evaluate(Hypothesis& h) const {
    int matched = 0;
    for (int o : h.slot_obs) matched += o >= 0;
    const int missing = static_cast<int>(pattern_.slots.size()) - matched;
    if (missing > params_.max_missing_markers && !params_.report_unidentified) return false;
    if (!fit(h)) return false;
    const Observed& team = observed_[h.team];
    double cost = 0;
    int terms = 0;
    auto position = [&](const MarkerShape& shape, const Observed& o) {
      const double r = (o.plane.centre - h.pose.apply({shape.x, shape.y})).norm();
      cost += (r / params_.position_sigma) * (r / params_.position_sigma);
      ++terms;
      return r <= params_.marker_gate;
    };
    auto area = [&](const MarkerShape& shape, const Observed& o) {
      const double expected = expectedMarkerArea(camera_, shape, h.pose.x, h.pose.y, h.pose.theta,
                                                 pattern_.robot_height);
      if (expected <= 0) return false;
      const double ratio = o.area_px / expected;
      const double l = std::log(ratio) / params_.area_sigma;
      cost += l * l;
      ++terms;
      return ratio <= params_.area_ratio_gate && ratio >= 1.0 / params_.area_ratio_gate;
    };
    if (h.heading_valid && !position(pattern_.team_marker, team)) return false;
    for (std::size_t s = 0; s < h.slot_obs.size(); ++s) {
      if (h.slot_obs[s] >= 0 && !position(pattern_.slots[s], observed_[h.slot_obs[s]])) return false;
    }
    if (teamAxisUsable(team) && h.heading_valid) {
      const double d = std::remainder(team.plane.minor_axis_angle - *team_axis_ - h.pose.theta, M_PI);
      const double l = d / (params_.axis_sigma_deg * kDeg);
      cost += l * l;
      ++terms;
    }
    // Ids compatible with the colours seen.
    std::vector<int> compatible;
    for (std::size_t id = 0; id < pattern_.ids.size(); ++id) {
      bool ok = true;
      for (std::size_t s = 0; s < h.slot_obs.size() && ok; ++s) {
        if (h.slot_obs[s] >= 0) ok = pattern_.ids[id][s] == observed_[h.slot_obs[s]].color;
      }
      if (ok) compatible.push_back(static_cast<int>(id));
    }
    const bool has_ids = !pattern_.ids.empty();
    if (has_ids && compatible.empty()) return false;
    const bool id_known = has_ids && compatible.size() == 1 && missing <= params_.max_missing_markers;
    h.id = id_known ? compatible.front() : -1;
    if (has_ids && !id_known && !params_.report_unidentified) return false;

    if (!area(pattern_.team_marker, team)) return false;
    for (std::size_t s = 0; s < h.slot_obs.size(); ++s) {
      if (h.slot_obs[s] >= 0 && !area(pattern_.slots[s], observed_[h.slot_obs[s]])) return false;
    }

    h.confidence = std::exp(-0.5 * cost / std::max(terms, 1)) * std::pow(params_.missing_marker_factor, missing);
    if (has_ids && !id_known) h.confidence = std::min(h.confidence, 0.2);
    return h.confidence >= params_.min_confidence;
  }

  const CameraModel& camera_;
  const PatternSet& pattern_;
  const RobotIdentificationParams& params_;
  Eigen::Vector2d team_pos_;
  std::vector<std::set<ColorClass>> slot_colors_;
  std::vector<double> slot_dist_, slot_angle_;
  double max_reach_ = 0;
  std::optional<double> team_axis_;  // minor axis of the team tag in the robot frame
  std::vector<Observed> observed_;
  std::vector<int> teams_, id_markers_;
};

}  // namespace

RobotIdentifier::RobotIdentifier(const CameraModel& camera, const PatternSet& patterns,
                                 const RobotIdentificationParams& params)
    : camera_(camera), patterns_(patterns), params_(params) {}

RobotIdentificationResult RobotIdentifier::identify(const std::vector<Region>& regions) const {
  const Matcher m(camera_, patterns_, params_, regions);
  const auto& obs = m.observed();
  std::vector<char> used(obs.size(), 0);
  std::set<std::pair<Team, int>> taken;

  // Greedy global assignment over each team region's current best hypothesis, best first.
  std::vector<std::vector<Hypothesis>> options(obs.size());
  using Entry = std::pair<double, int>;  // confidence, team observation
  std::priority_queue<Entry> queue;
  for (int t : m.teams()) {
    options[t] = m.hypotheses(t, used, taken);
    if (!options[t].empty()) queue.push({options[t].front().confidence, t});
  }
  std::vector<Hypothesis> accepted;
  std::vector<char> done(obs.size(), 0);
  while (!queue.empty()) {
    const int t = queue.top().second;
    queue.pop();
    if (done[t] || used[t] || options[t].empty()) continue;
    const Hypothesis& h = options[t].front();
    const auto parts = h.observedUsed();
    const bool conflict = std::any_of(parts.begin(), parts.end(), [&](int o) { return used[o] != 0; }) ||
                          (h.id >= 0 && taken.count({obs[t].color == ColorClass::Blue ? Team::Blue : Team::Yellow, h.id}));
    if (conflict) {
      // Regions taken since this was formed: form the hypotheses again without them.
      options[t] = m.hypotheses(t, used, taken);
      if (!options[t].empty()) queue.push({options[t].front().confidence, t});
      continue;
    }
    for (int o : parts) used[o] = 1;
    done[t] = 1;
    const Team team = obs[t].color == ColorClass::Blue ? Team::Blue : Team::Yellow;
    if (h.id >= 0) taken.insert({team, h.id});
    accepted.push_back(h);
  }

  RobotIdentificationResult out;
  out.region_used.assign(regions.size(), false);
  for (std::size_t o = 0; o < obs.size(); ++o) {
    if (used[o]) out.region_used[obs[o].region] = true;
  }
  for (const Hypothesis& h : accepted) {
    RobotDetection d;
    d.team = obs[h.team].color == ColorClass::Blue ? Team::Blue : Team::Yellow;
    d.id = h.id;
    d.x = h.pose.x;
    d.y = h.pose.y;
    d.heading_valid = h.heading_valid;
    d.theta = h.heading_valid ? wrapAngle(h.pose.theta) : 0.0;
    d.confidence = h.confidence;
    const auto px = camera_.project({d.x, d.y, patterns_.robot_height});
    const Region& team_region = regions[obs[h.team].region];
    d.pixel = px ? *px : Eigen::Vector2d(team_region.cx, team_region.cy);
    out.robots.push_back(d);
  }
  std::sort(out.robots.begin(), out.robots.end(),
            [](const RobotDetection& a, const RobotDetection& b) { return a.confidence > b.confidence; });
  return out;
}

}  // namespace soccer_vision
