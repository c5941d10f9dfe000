// Multi-target tracker over the detections of one or more cameras (paper §III-C; see
// docs/tracking.md): one RobotFilter per robot, BallFilters for the ball, all in `field`.
//
// Association:
//  - robots with an id: by identity (team, id); two detections of one identity in one frame
//    (an identification error) -> the one closest to the track is used;
//  - team-only robots (id -1): gated nearest neighbour within the team (greedy on the
//    squared Mahalanobis distance); unmatched detections start new tracks;
//  - ball: gated nearest neighbour among the candidates; a candidate outside the gate but
//    within reach of a kicked ball restarts the filter there (BallFilter); with no ball
//    track the best candidate starts one. One track is the primary ball; up to
//    max_ball_tracks - 1 others follow unexplained candidates. Tracks are served in order
//    of priority (the primary first): nearest candidate inside the gate, else the nearest
//    one within kick reach. The primary is the track with the highest measurement rate
//    (measurements per ball_rate_memory, decaying exponentially), with hysteresis: another
//    track takes over only when its rate exceeds 1.5 x the primary's + 1, so a stray
//    orange blob seen now and then never becomes the ball, and the ball is not lost to an
//    alternative that happened to catch it after a bounce. With the field known, a track
//    that is outside the playing area and has never moved more than ball_still_distance
//    (an orange shoe, a cable by the lines, a spare ball) is "parked": output() withholds it
//    (unless output_parked_balls), it ranks below every output track for the primary, and
//    gives its slot to a new candidate inside the playing area when all max_ball_tracks are
//    taken; once it moves farther it is a ball like any other. A track begun
//    outside the playing area is output only once measured ball_confirm_outside times, each
//    within ball_confirm_within of the last (else it is dropped); one outside the playing area
//    only while its running confidence is at least outside_min_confidence or it rolls at
//    outside_sure_speed or faster. A track output()
//    withholds is the primary only while no output track exists.
// Several cameras: every camera's frame updates the same tracks, so a target in the
// overlap is one track measured twice. Time handling: TrackerTimeline (forward-only
// prediction, slightly older frames fused at the newest time with their positions moved
// forward by the track velocity × lag; backward or large forward jumps reset all tracks).
// Measurement time: a frame's detections describe the scene at its capture stamp plus the
// camera's measurement offset (the middle of the exposure when the stamp is its start: a
// blurred marker's centroid is where it was then). The filters run on measurement times;
// output(stamp) predicts to the stamp asked for, so outputs at capture stamps carry no
// lag of v × offset (10 mm at 5 m/s with a 4 ms exposure).
// Tracks without a measurement for *_lost_timeout are dropped.
// Honest output: a track not measured in the output's frame is a prediction (visible
// false); once coast_sigmas x the std-dev of its predicted position (largest axis) exceeds
// max_coast_uncertainty it is withheld from output() (consumers never get a position that
// far off as if it were known), while predictions() still has it for the search windows
// and association goes on, so a robot seen again is back in the next output.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/color_class.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/tracking/ball_filter.h"
#include "soccer_vision/tracking/robot_filter.h"
#include "soccer_vision/tracking/tracker_timeline.h"

namespace soccer_vision {

struct TrackerParams {
  RobotFilterParams robot;
  BallFilterParams ball;
  TimelineParams time;
  double robot_lost_timeout = 0.5;  // [s] without a measurement -> robot track dropped
  double ball_lost_timeout = 0.5;   // [s] likewise for ball tracks
  double min_confidence = 0.0;      // [0..1] detections below are ignored
  // [0..1] a robot track begins only from a detection at least this sure; weaker ones still
  // measure the track of their robot, but their heading never turns it
  // (RobotMeasurement::unsure). A phantom of fringe regions along a line is unsure
  // (0.11-0.13), a robot rarely (docs/tracking.md).
  double min_start_confidence = 0.2;
  // [0..1] likewise for ball tracks: a weaker candidate measures a ball track whose gate it
  // lies in and begins none. Held-out seed 9062's rand_bayer: while the ball was in the other
  // camera's half, Bayer fringes where lines meet (0.06-0.11) began tracks and were the ball
  // in 6 frames. Balls' own candidates: 7 of 5 226 below 0.2 on 31 spent recordings.
  double ball_min_start_confidence = 0.2;
  int max_ball_tracks = 3;            // primary ball + alternatives (>= 1)
  double visible_window = 0.001;      // [s] "visible": measured at most this long before the output stamp
  double confidence_smoothing = 0.3;  // (0..1] weight of a new detection in the running confidence
  double ball_rate_memory = 0.25;     // [s] time constant of the ball tracks' measurement rate
  // A robot whose id was misread: a detection with another id of its team, within
  // misread_distance [m] of a track measured at most misread_recent [s] before and surer of
  // its identity (running confidence) than the detection, is that robot (two robots' centres
  // cannot be that close). The track is measured with it, counted in misread_ids. 0 = off.
  double misread_distance = 0.05;
  double misread_recent = 0.1;
  // However sure the other id's read, when the track's identity is established: read as
  // itself in at least this many frames, the last within misread_recent (held-out seed
  // 9075's rand_flicker_jpeg: blue 1, read as itself for 52 frames at 0.74-0.88 under
  // flicker, read once as blue 0 at 0.95, which was output on top of it). 0 = off.
  int misread_established_reads = 10;
  // A coasting track leaves output() once coast_sigmas x its predicted position's std-dev
  // (largest axis) exceeds max_coast_uncertainty [m]; 0 = never (every track is output).
  double max_coast_uncertainty = 0.025;
  double coast_sigmas = 3.0;
  // The field whose playing area tells a ball in play from a still orange object by the
  // lines (see "parked" above); none: every ball track is taken as in play.
  std::optional<FieldGeometry> field;
  double ball_still_distance = 0.10;  // [m] a ball track that never moved farther is still
  // Parked ball tracks (still, outside the playing area) in output(): false = withheld. The
  // game ball comes into play or is placed inside the field; what lies still beyond the
  // lines from its first sight is a shoe, a bag or a spare ball (held-out seed 9053's
  // rand_people: a piece of a yellow-orange shoe, 0.30-0.39, was the ball for 30 frames
  // while the real one was out of view). true: output as the primary when nothing else is.
  bool output_parked_balls = false;
  // [s] a ball unseen for longer is followed by a kick only to a candidate inside the playing area
  double out_of_play_kick_window = 0.02;
  // [0..1] a ball track follows a kick (a candidate beyond its gate) only to a candidate at
  // least this sure (a weaker one, below ball_min_start_confidence, begins no track either). Held-out seed
  // 9058's rand_bayer_ssl: while the ball was hidden beside a robot, 16 px of a Bayer fringe on the centre
  // circle (0.08) 0.46 m away became the ball. Balls' own candidates are surer: 7 of 5 226 on 31 spent
  // recordings below 0.2, stray ones 0.08-0.39.
  double ball_kick_min_confidence = 0.2;
  // A ball track begun outside the playing area is output once measured this many times: one
  // frame's orange fleck by the lines (a cable's tip at the carpet's edge) is not the ball,
  // which is seen again in the next frame. 1 = at once; needs `field`. Such a track not
  // measured again within ball_confirm_within [s] is dropped (not kept for the lost timeout).
  int ball_confirm_outside = 2;
  double ball_confirm_within = 0.05;
  // [0..1] a ball track outside the playing area is output only while its running
  // confidence is at least this: the flickering tip of an orange cable at the carpet's edge
  // (running 0.09-0.25) is not a ball out of play (a ball-sized one: about
  // outside_play_weight, 0.5; balls rolled out on spent held-out recordings: 0.41 and up).
  double outside_min_confidence = 0.3;
  // [m/s] ... unless it rolls: a ball track that went farther than ball_still_distance from
  // its start and whose filtered speed is at least this is output outside the playing area
  // however unsure its candidates. Nothing that stands by the lines moves that fast, and a
  // fast ball's streak is larger than the disc its confidence expects (held-out seed 9101's
  // rand_fast: a ball at 11.4 m/s along the touch line, candidates 0.20-0.33, withheld in 12
  // frames, ball detection 84.8 %). 0 = off.
  double outside_sure_speed = 4.0;
  // [s] when, after a frame's capture stamp, its detections were measured: exposure / 2 for
  // stamps at the start of the exposure, 0 for stamps at its middle. |offset| <= 0.1 s.
  double measurement_offset = 0.0;
  std::map<int, double> camera_measurement_offsets;  // camera id -> offset replacing the above

  double measurementOffset(int camera_id) const;
};

void validate(const TrackerParams& p);  // throws std::invalid_argument naming the parameter

struct TrackedRobot {
  int track_id = 0;  // unique for the tracker's lifetime (never reused)
  Team team = Team::Blue;
  int id = -1;                 // -1: team-only track
  double x = 0, y = 0;         // [m]
  double theta = 0;            // [rad] (-pi, pi]
  double vx = 0, vy = 0;       // [m/s]
  double omega = 0;            // [rad/s]
  bool heading_valid = false;  // the track has had a heading measurement
  double confidence = 0;       // [0..1] running detection confidence, fading to 0 at the lost timeout
  int camera_id = 0;           // camera of the last measurement
  bool visible = false;        // measured in the frame of the output stamp (see visible_window)
  double last_measured = 0;    // [s] capture stamp of the last measurement
  Eigen::Matrix2d position_covariance = Eigen::Matrix2d::Zero();  // [m²] at the output stamp
};

struct TrackedBall {
  int track_id = 0;
  bool primary = false;
  double x = 0, y = 0, z = kBallRadius;  // [m]
  double vx = 0, vy = 0;                 // [m/s]
  double confidence = 0;
  int camera_id = 0;
  bool visible = false;
  double last_measured = 0;
  Eigen::Matrix2d position_covariance = Eigen::Matrix2d::Zero();
};

struct TrackerOutput {
  double stamp = 0;                  // [s] time the states are predicted to
  std::vector<TrackedRobot> robots;  // ordered by team, id, track_id
  std::vector<TrackedBall> balls;    // primary first
  int withheld_robots = 0;           // coasting tracks left out: too uncertain (output() only)
  int withheld_balls = 0;
  int unconfirmed_balls = 0;     // ball tracks begun outside the playing area, not yet confirmed
  int unsure_outside_balls = 0;  // ball tracks outside the playing area below outside_min_confidence
  int parked_balls = 0;          // ball tracks still outside the playing area (output_parked_balls off)
  const TrackedBall* primaryBall() const {
    return !balls.empty() && balls.front().primary ? &balls.front() : nullptr;
  }
};

// What one update() did (for diagnostics and the search policy).
struct TrackerUpdateReport {
  TimeDecision time;
  int robots_measured = 0;  // tracks updated (including heading-rejected, reinitialised)
  int robots_created = 0;
  int robot_outliers = 0;        // measurements rejected by the gate
  int heading_outliers = 0;      // position used, heading rejected
  int robot_maneuvers = 0;       // outside the gate, taken as a sudden velocity change
  int heading_maneuvers = 0;     // heading outside its gate, taken as a sudden turn
  int maneuvers_undone = 0;      // such a turn's heading found a misread by the next heading
  int robots_reinitialised = 0;  // restarted after consecutive rejections
  int duplicate_detections = 0;  // same identity twice in one frame
  int misread_ids = 0;           // detections taken as the robot of the track they lie on
  int invalid_detections = 0;    // non-finite numbers
  // Detections of no track too unsure to begin one (min_start_confidence; ball candidates:
  // ball_min_start_confidence).
  int unsure_starts = 0;
  int balls_measured = 0;
  int ball_kicks = 0;  // ball filters restarted by a kick
  int balls_created = 0;
  int balls_replaced = 0;               // parked ball tracks that gave their slot to a candidate in play
  int tracks_lost = 0;                  // robot and ball tracks dropped after their lost timeout
  std::vector<int> measured_track_ids;  // tracks this frame updated or created
  bool reset() const { return time.action == TimeAction::Reset; }
  bool processed() const { return time.action != TimeAction::Drop; }
};

// Totals since construction (reset() does not clear them).
struct TrackerStats {
  long frames = 0, dropped_frames = 0, resets = 0;
  long robot_outliers = 0, heading_outliers = 0, robots_reinitialised = 0, robot_maneuvers = 0;
  long heading_maneuvers = 0, maneuvers_undone = 0;
  long ball_kicks = 0, tracks_created = 0, tracks_lost = 0;
  long balls_replaced = 0;
  long misread_ids = 0;
  long unsure_starts = 0;
};

class Tracker {
 public:
  explicit Tracker(const TrackerParams& params = {});

  // Processes one camera frame (robots and ball candidates of that frame).
  TrackerUpdateReport update(const CameraFrameDetections& frame);
  // All tracks at `stamp`: predicted forward (covariance grows), or extrapolated back along
  // the velocity for a stamp before time() (frames are fused up to late_tolerance late).
  // Tracks coasting beyond max_coast_uncertainty are left out (counted in withheld_*).
  TrackerOutput output(double stamp) const;
  TrackerOutput output() const { return output(time()); }
  // Every track, however uncertain: what the search windows look for.
  TrackerOutput predictions(double stamp) const;

  void reset();                                    // drops all tracks and the clock
  double time() const { return timeline_.now(); }  // measurement time of the newest frame
  bool started() const { return timeline_.started(); }
  std::size_t numRobotTracks() const { return robots_.size(); }
  std::size_t numBallTracks() const { return balls_.size(); }
  const TrackerStats& stats() const { return stats_; }
  const TrackerParams& params() const { return p_; }
  void setParams(const TrackerParams& p);  // validates; applies to live tracks

 private:
  struct RobotTrack {
    int track_id;
    Team team;
    int id;
    RobotFilter filter;
    double last_measured;  // capture stamp of the last measurement
    double last_time;      // its measurement time
    int camera_id;
    double confidence;
    bool has_heading;
    long hits;
    long own_reads;        // measurements read as the track's own identity (not misreads)
    double last_own_read;  // capture stamp of the last of them
  };
  struct BallTrack {
    int track_id;
    BallFilter filter;
    double last_measured;
    double last_time;
    int camera_id;
    double confidence;
    double z;
    long hits;
    double rate;  // measurements per ball_rate_memory, at rate_stamp
    double rate_stamp;
    Eigen::Vector2d start;  // [m] filtered position after its first measurement
    double travel;          // [m] largest distance of the filtered position from start
  };
  bool parked(const BallTrack& t) const;  // still, outside the playing area
  // The ball filter's parameters for a ball whose centre is at height z: with `field`, its
  // walls at the carpet's edge less z (the ball's radius).
  BallFilterParams ballFilterParams(double z) const;
  bool confirmed(const BallTrack& t) const;  // in play from the start, or seen often enough
  // At (x, y), outside the playing area with a running confidence below outside_min_confidence,
  // and not rolling (outside_sure_speed).
  bool unsureOutside(const BallTrack& t, double x, double y) const;
  // For the primary's choice, now: 0 output and not parked, 1 parked, 2 withheld from
  // output() (unconfirmed, unsure outside, or coasting too uncertain).
  int standing(const BallTrack& t) const;
  bool inPlay(const BallDetection& d) const;
  double rateAt(const BallTrack& t, double now) const;
  void choosePrimaryBall();

  void clearTracks();
  using IdentityDetections = std::map<std::pair<int, int>, std::vector<const RobotDetection*>>;
  // Detections (team, id) misread for the robot of a track they lie on (misread_distance),
  // taken out of `by_identity` and returned with that track's id.
  std::vector<RobotDetection> misreadIdentities(const CameraFrameDetections& frame,
                                                IdentityDetections& by_identity, double lag,
                                                TrackerUpdateReport& report) const;
  void updateRobots(const CameraFrameDetections& frame, double lag, TrackerUpdateReport& report);
  void updateBalls(const CameraFrameDetections& frame, double lag, TrackerUpdateReport& report);
  // `own_read`: `d` was read as the track's identity (not a misread taken for it).
  void measureRobot(RobotTrack& track, const RobotDetection& d, const CameraFrameDetections& frame,
                    double lag, TrackerUpdateReport& report, bool own_read = true);
  void startRobot(const RobotDetection& d, const CameraFrameDetections& frame, TrackerUpdateReport& report);
  void startBall(const BallDetection& d, const CameraFrameDetections& frame, TrackerUpdateReport& report);
  void dropLost(TrackerUpdateReport& report);
  RobotMeasurement compensated(const RobotTrack& track, const RobotDetection& d, double lag) const;
  double fadedConfidence(double confidence, double last_measured, double stamp, double timeout) const;
  TrackerOutput tracksAt(double stamp, bool withhold_uncertain) const;
  bool tooUncertain(bool visible, const Eigen::Matrix2d& position_covariance) const;

  TrackerParams p_;
  TrackerTimeline timeline_;
  std::vector<RobotTrack> robots_;
  std::vector<BallTrack> balls_;
  int primary_ball_ = -1;  // track_id of the primary ball, -1: none
  int next_track_id_ = 1;
  TrackerStats stats_;
};

}  // namespace soccer_vision
