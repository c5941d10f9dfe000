// When one camera's next frame is searched as a whole instead of in the search windows
// (paper §III-C: windows follow known targets; a global search finds new ones):
//  - the first frame, and the first after the tracker reset its time line;
//  - when there are no tracks at all;
//  - when a target expected in this camera (predicted centre inside the image, see
//    SearchWindow::expected) was not measured in this camera's last frame, if that frame
//    was searched in windows (a miss of the whole-frame search is looked for in the next
//    frame's windows first);
//  - at least every period_frames processed frames (1: always; 0: never periodically).
// Per camera, per processed frame:
//   report = tracker.update(frame);  policy.observe(report);
//   windows = searchWindows(tracker.predictions(next_stamp), camera, interval);
//   global = policy.decide(windows, tracker.numRobotTracks() + tracker.numBallTracks()) != None;
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "soccer_vision/tracking/search_windows.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

enum class GlobalSearchReason { None, First, AfterReset, NoTracks, TargetMissing, Periodic };
constexpr int kNumGlobalSearchReasons = 6;
const char* globalSearchReasonName(GlobalSearchReason r);

struct GlobalSearchParams {
  int period_frames = 30;  // [processed frames] global search at least this often (0: never)
};

void validate(const GlobalSearchParams& p);  // throws std::invalid_argument

class GlobalSearchPolicy {
 public:
  explicit GlobalSearchPolicy(const GlobalSearchParams& params = {});

  // After the tracker processed this camera's frame (searched with the windows of the
  // last decide()): notes which expected targets it missed and whether time was reset.
  // `searched_whole`: that frame was searched whole, as one without a plan yet is (the
  // first): then it was the first search, and the next decide() need not repeat it.
  void observe(const TrackerUpdateReport& report, bool searched_whole = false);
  // How to search this camera's next frame, given the windows predicted for it and the
  // number of live tracks. Returns None for a windowed search.
  GlobalSearchReason decide(const std::vector<SearchWindow>& next_windows, std::size_t num_tracks);

  void restart();  // next decision: First
  // Targets expected by the last decide() that the last observed frame did not measure.
  const std::vector<int>& missing() const { return missing_; }
  long count(GlobalSearchReason r) const { return counts_[static_cast<int>(r)]; }
  const GlobalSearchParams& params() const { return p_; }
  void setParams(const GlobalSearchParams& p);

 private:
  GlobalSearchParams p_;
  bool first_ = true;
  bool reset_seen_ = false;
  std::vector<int> expected_;  // track ids expected in the frame being searched
  std::vector<int> missing_;
  int frames_since_global_ = 0;
  bool searched_whole_ = false;  // the last decide() planned a whole-frame search
  std::array<long, kNumGlobalSearchReasons> counts_{};
};

}  // namespace soccer_vision
