// The four figures of the offline evaluation (`evaluate --plots DIR`, issue 5): trajectories
// on the field, per-frame position error, per-stage timing histograms, and the Kalman
// prediction error per frame step (the paper's Fig. 6 as an error over time).
//
// Inputs are plain data filled by the evaluation; missing values are NaN. Each figure has a
// render* function returning the BGR image and a plot* function writing it as a PNG; the
// plot* functions throw std::runtime_error naming the path when it cannot be written, and
// all throw std::invalid_argument for inconsistent input (vectors of different lengths).
// Empty input gives a figure that says "no data". Times are shown relative to the earliest
// time of the figure (bag stamps are seconds since 1970).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/field_geometry.h"

namespace soccer_vision {

// One target over the run: ground truth and the tracker's output at the same times t (s).
struct TrajectorySeries {
  std::string label;  // legend text, e.g. "blue 3", "ball"
  std::string team;   // "blue" or "yellow" picks the team's shades; anything else (ball) others
  // All the same length: s, then m in the field frame; NaN where missing.
  std::vector<double> t, truth_x, truth_y, tracked_x, tracked_y;
};

// Per-frame position error against ground truth (mm), NaN where nothing was matched.
// Each error vector is either empty (not evaluated) or as long as t.
struct ErrorSeries {
  std::vector<double> t;               // s
  std::vector<double> robot_error_mm;  // e.g. mean over the frame's matched robots
  std::vector<double> ball_error_mm;
};

// Per-frame processing time of each pipeline stage: ms[i] are the times of stage[i].
struct StageTimes {
  std::vector<std::string> stage;
  std::vector<std::vector<double>> ms;
};

// Distance (mm) between the position the Kalman filter predicted for the next processed
// frame and the ground truth there, when every frame_step-th frame is processed.
struct PredictionErrorSeries {
  int frame_step = 1;  // >= 1
  std::vector<double> t, error_mm;
};

// Field (carpet, white lines, goals) with each target's ground truth as a broad pale line
// and its tracked positions as a dashed line of the same colour, equal aspect, metres. The
// axes end 0.2 m beyond the carpet; positions further out are counted under the x axis.
cv::Mat renderTrajectories(const std::vector<TrajectorySeries>& series, const FieldGeometry& field);
void plotTrajectories(const std::vector<TrajectorySeries>& series, const FieldGeometry& field,
                      const std::string& png_path);

// Robot and ball error against time, RMS and p95 in the legend.
cv::Mat renderPositionError(const ErrorSeries& errors);
void plotPositionError(const ErrorSeries& errors, const std::string& png_path);

// One histogram per stage (small multiples), p50 and p99 marked and in the legend. A long
// tail beyond 2·p99 is cut off and counted under the axis.
cv::Mat renderStageTimingHistogram(const StageTimes& times);
void plotStageTimingHistogram(const StageTimes& times, const std::string& png_path);

// One panel per frame step (sorted), shared axes so the panels compare, RMS per step in the
// legend and the title.
cv::Mat renderPredictionError(const std::vector<PredictionErrorSeries>& series);
void plotPredictionError(const std::vector<PredictionErrorSeries>& series, const std::string& png_path);

// The colours the figures use (BGR), public so callers and tests can refer to them.
// index-th target of a team (in the order the series are given; cycles after 8).
cv::Scalar trajectoryColor(const std::string& team, int index);
// The pale version of a colour the ground-truth lines are drawn with.
cv::Scalar truthShade(const cv::Scalar& color);
cv::Scalar robotErrorColor();
cv::Scalar ballErrorColor();
cv::Scalar stageColor(int stage_index);
cv::Scalar predictionErrorColor();

}  // namespace soccer_vision
