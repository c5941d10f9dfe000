// How one camera's next frame is searched (paper §III-C): in the windows of the tracks
// predicted to that frame's stamp, plus the entry bands along the image borders, or as a
// whole (GlobalSearchPolicy). The Tracking nodelet and the in-process VisionPipeline both
// plan with it, so that live and offline runs make the same decisions.
//
// Per camera, per frame the tracker was given:
//   report = tracker.update(frame);   planner.observe(report, frame.stamp);
//   plan = planner.plan(tracker, &camera_model, frame.stamp);
// The next frame's stamp is predicted as this one's plus the mean interval between the
// camera's processed frames (an exponential average, so frame_step and dropped frames are
// accounted for).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/tracking/global_search_policy.h"
#include "soccer_vision/tracking/search_windows.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

struct SearchPlannerParams {
  bool search_windows = true;  // false: every frame is searched whole (reason Periodic)
  int entry_band_px = 48;      // bands along the image borders searched with the windows
  SearchWindowParams windows;  // windows.side_px = R
  GlobalSearchParams global_search;
  // The periodic global search as a sweep: instead of the whole frame every
  // global_search.period_frames frames, every windowed frame also searches one of
  // period_frames horizontal stripes in turn, grown by entry_band_px above and below (so
  // that a robot fits whole into one of two neighbouring stripes): the same coverage,
  // without the whole frame's latency spike. The other reasons still search whole.
  bool sweep = true;
  // The primary ball's window is a streak window (SearchPlan::ball_streak_rects) while its
  // track was measured within this many frame intervals of the planned frame: a ball kicked
  // during one frame's exposure may be missed there (its streak bent by the kick) and still
  // followed; not one searched for long after it was lost. docs/segmentation.md.
  double ball_streak_intervals = 3.5;
  // While no ball was seen within ball_streak_intervals (lost, or not yet found), the entry
  // bands and the sweep's stripe within the image of the playing area (the tracker's field)
  // are streak windows too (SearchPlan::lost_ball_streak_rects; not on Bayer quads): a ball
  // coming into view faster than the colour table's orange reaches is found as it comes
  // through a band, or within a sweep, not only once it slows down. Not beyond the lines,
  // where the carpet's edge and what stands outside read as ball mixed with carpet.
  bool lost_ball_sweep_streaks = true;
  // A robot candidate identification rejected after finding markers around its team region
  // (a RejectedRobotCandidate with a cause other than projection or unpaired: lookAgainAt)
  // gets a window of windows.side_px about it in the camera's next candidate_frames frames,
  // for as long as it is rejected again, at most max_candidates at a time: a robot the
  // first whole-frame search saw but could not identify is looked at again in the next
  // frames, not only when the sweep's stripe comes by up to global_search.period_frames
  // later (held-out seed 9094's rand_bayer_ssl: a robot in the wide-angle corner, rejected
  // in the first frame, unsearched for 24). 0 = off.
  int candidate_frames = 10;
  int max_candidates = 4;
};

void validate(const SearchPlannerParams& p);  // throws std::invalid_argument

struct SearchPlan {
  double stamp = 0;  // the predicted stamp of the frame this plan is for
  // The policy's decision (Periodic for every frame when search windows are off).
  GlobalSearchReason reason = GlobalSearchReason::First;
  bool global_search = true;          // searched whole: a reason, or no camera model to project with
  std::vector<SearchWindow> windows;  // the tracks' windows (also when searching whole)
  std::vector<cv::Rect> rects;  // windows + entry bands (+ the sweep's stripe); empty for a global search
  cv::Rect sweep_stripe;        // the stripe of SearchPlannerParams::sweep in rects; empty: none
  // The primary ball's window when its track was measured within
  // SearchPlannerParams::ball_streak_intervals of this plan's stamp (also when searching
  // whole), else none: where the Segmenter takes orange from the ball's streak table (a
  // ball seen until a moment ago, kicked since). Not for a ball searched for after it was
  // lost (out of view, hidden): its window would be filled with whatever reads as ball and
  // carpet, such as Bayer fringes at the carpet's edge.
  std::vector<cv::Rect> ball_streak_rects;
  // SearchPlannerParams::lost_ball_sweep_streaks: the entry bands and the sweep's stripe
  // within the playing area's image while no ball was seen; the segmentation searches them
  // with the streak table where that suits the image's layout (searchesLostBallStreaks in
  // segmenter.h).
  std::vector<cv::Rect> lost_ball_streak_rects;
};

class SearchPlanner {
 public:
  explicit SearchPlanner(const SearchPlannerParams& params = {});

  // The tracker has processed (or refused) this camera's frame of `stamp`, which was
  // searched whole or not (GlobalSearchPolicy::observe), and identification rejected these
  // robot candidates in it.
  void observe(const TrackerUpdateReport& report, double stamp, bool searched_whole = false,
               const std::vector<RejectedRobotCandidate>& rejected = {});
  // The plan for the camera's next frame. Without a camera model (not known yet) the frame
  // is searched whole.
  SearchPlan plan(const Tracker& tracker, const CameraModel* camera, double stamp);
  // The tracker dropped its tracks (a time jump seen by any camera): next plan is First.
  void restart() {
    policy_.restart();
    next_stripe_ = 0;
    candidates_.clear();
  }

  // [s] mean interval between processed frames; 1/60 until two frames were seen.
  double interval() const { return interval_ > 0 ? interval_ : 1.0 / 60; }
  const GlobalSearchPolicy& policy() const { return policy_; }
  const SearchPlannerParams& params() const { return params_; }
  void setParams(const SearchPlannerParams& params);  // throws std::invalid_argument

 private:
  SearchPlannerParams params_;
  GlobalSearchPolicy policy_;
  double last_stamp_ = 0, interval_ = 0;
  int next_stripe_ = 0;  // of the sweep
  struct Candidate {
    Eigen::Vector2d pixel;
    int frames_left = 0;
  };
  std::vector<Candidate> candidates_;  // rejected robot candidates looked at again
};

// Whether a rejected robot candidate looks like a robot that may be identified in the next
// frame: its team region had markers around it (not unpaired) on the plane (not projection).
bool lookAgainAt(const RejectedRobotCandidate& candidate);

// Stripe `index` of `count` of an image (SearchPlannerParams::sweep): rows [index·h/count,
// (index+1)·h/count) grown by `margin` rows above and below, clipped to the image.
cv::Rect sweepStripe(cv::Size image, int index, int count, int margin);
// The image rectangle (clipped to the image) that encloses the playing area's lines as the
// camera sees them; empty when none of them projects.
cv::Rect playingAreaImageRect(const CameraModel& camera, const FieldGeometry& field);

}  // namespace soccer_vision
