// Search windows (paper §III-C): where the next frame of one camera is searched, from the
// tracker's prediction for that frame. A window is a square of side R pixels centred on
// the projection of the predicted position (robots at their team's marker height, 0.150 m
// unless the pattern says otherwise; the ball at its centre, kBallRadius), grown on each side by
//  - sigma_scale × the largest std-dev of the predicted position (the window keeps up with
//    the prediction's uncertainty: long gaps, new tracks with unknown velocity), and
//  - for the ball, ball_speed_margin × the distance it travels in one frame interval (a
//    fast ball bounces or is deflected: the faster, the larger the window),
// both converted to pixels through the camera model at the target's position, then capped
// at max_side_px, clipped to the image, and dropped when nothing of it is in the image.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/types.hpp>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/color_class.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

struct SearchWindowParams {
  int side_px = 200;  // R [px], side of the window before enlargement
  // [m] plane of the robot markers per team (PatternSet::heights).
  TeamHeights robot_height{0.150, 0.150};
  double ball_height = kBallRadius;  // [m] plane of the ball centre
  double sigma_scale = 3.0;          // grow by this many std-devs of the predicted position (0: off)
  double ball_speed_margin = 0.5;    // grow ball windows by this fraction of one frame's travel (0: off)
  int max_side_px = 800;             // [px] cap on the enlarged side
  double expected_margin_px = 20;    // [px] a target is expected in this camera when its
                                     //      predicted centre is this far inside the image
  bool alternative_balls = true;     // windows also for the non-primary ball tracks
};

void validate(const SearchWindowParams& p);  // throws std::invalid_argument

struct SearchWindow {
  enum class Target { Robot, Ball };
  cv::Rect rect;  // [px] in the raw image, clipped to it (non-empty)
  Target target = Target::Robot;
  int track_id = 0;
  Team team = Team::Blue;        // robots only
  int id = -1;                   // robots only; -1 team-only
  Eigen::Vector2d centre{0, 0};  // [px] predicted projection (may lie outside the image)
  bool expected = false;         // centre inside the image (margin): should be seen in this frame
  bool primary_ball = false;     // the window of the primary ball's track
  double last_measured = 0;      // [s] stamp of the ball track's last measurement (balls only)
};

// Windows for the frame the prediction was made for (`predicted` = Tracker::predictions(stamp of
// that frame)). frame_interval [s]: time between this camera's processed frames
// (frame_step / fps), for the ball speed margin.
std::vector<SearchWindow> searchWindows(const TrackerOutput& predicted, const CameraModel& camera,
                                        double frame_interval, const SearchWindowParams& params = {});

// The pixels whose centres lie in [c - half, c + half) in x and y (a square 2 * half wide),
// clipped to the image; none when nothing of it is in the image or `centre` is not finite.
// Every window about a pixel (a track's prediction, a rejected candidate) is this square.
std::optional<cv::Rect> squareAbout(const Eigen::Vector2d& centre, double half, cv::Size image);

// The rectangles alone, as the Segmenter takes them.
std::vector<cv::Rect> windowRects(const std::vector<SearchWindow>& windows);

// Bands of band_px along the four image borders (not overlapping; each at most half the
// image): where a robot or ball not tracked yet enters the view. Searched with the
// windows, they let a newcomer be found when it appears instead of at the next periodic
// global search. Empty for band_px <= 0.
std::vector<cv::Rect> entryBands(cv::Size image, int band_px);

}  // namespace soccer_vision
