#include "soccer_vision/tracking/global_search_policy.h"

#include <algorithm>
#include <stdexcept>

namespace soccer_vision {

const char* globalSearchReasonName(GlobalSearchReason r) {
  switch (r) {
    case GlobalSearchReason::None:
      return "none";
    case GlobalSearchReason::First:
      return "first";
    case GlobalSearchReason::AfterReset:
      return "after_reset";
    case GlobalSearchReason::NoTracks:
      return "no_tracks";
    case GlobalSearchReason::TargetMissing:
      return "target_missing";
    case GlobalSearchReason::Periodic:
      return "periodic";
  }
  return "?";
}

GlobalSearchPolicy::GlobalSearchPolicy(const GlobalSearchParams& params) { setParams(params); }

void validate(const GlobalSearchParams& p) {
  if (p.period_frames < 0) throw std::invalid_argument("global search: period_frames must be >= 0");
}

void GlobalSearchPolicy::setParams(const GlobalSearchParams& p) {
  validate(p);
  p_ = p;
}

void GlobalSearchPolicy::restart() {
  first_ = true;
  searched_whole_ = false;
  reset_seen_ = false;
  expected_.clear();
  missing_.clear();
  frames_since_global_ = 0;
}

void GlobalSearchPolicy::observe(const TrackerUpdateReport& report, bool searched_whole) {
  missing_.clear();
  if (!report.processed()) return;  // dropped frame: it says nothing about the targets
  if (report.reset()) {
    reset_seen_ = true;
    return;  // the expected tracks belonged to the old time line
  }
  if (searched_whole) first_ = false;  // the first search was this frame's
  // A target a whole-frame search did not find is not where windows could miss it: the
  // next (windowed) frame looks for it in its grown window, and only a miss there
  // calls for the whole frame again. (Under heavy noise, where a robot is missed now and
  // then wherever it is, a whole-frame search would otherwise follow every one.)
  if (searched_whole_) return;
  for (int id : expected_) {
    if (std::find(report.measured_track_ids.begin(), report.measured_track_ids.end(), id) ==
        report.measured_track_ids.end()) {
      missing_.push_back(id);
    }
  }
}

GlobalSearchReason GlobalSearchPolicy::decide(const std::vector<SearchWindow>& next_windows,
                                              std::size_t num_tracks) {
  GlobalSearchReason reason = GlobalSearchReason::None;
  if (first_) {
    reason = GlobalSearchReason::First;
  } else if (reset_seen_) {
    reason = GlobalSearchReason::AfterReset;
  } else if (num_tracks == 0) {
    reason = GlobalSearchReason::NoTracks;
  } else if (!missing_.empty()) {
    reason = GlobalSearchReason::TargetMissing;
  } else if (p_.period_frames > 0 && frames_since_global_ + 1 >= p_.period_frames) {
    reason = GlobalSearchReason::Periodic;
  }
  first_ = reset_seen_ = false;
  missing_.clear();
  expected_.clear();
  for (const auto& w : next_windows) {
    if (w.expected) expected_.push_back(w.track_id);
  }
  frames_since_global_ = reason == GlobalSearchReason::None ? frames_since_global_ + 1 : 0;
  searched_whole_ = reason != GlobalSearchReason::None;
  ++counts_[static_cast<int>(reason)];
  return reason;
}

}  // namespace soccer_vision
