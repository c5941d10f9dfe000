#include "evaluation_plots.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "plot_canvas.h"
#include "soccer_vision/common/statistics.h"

namespace soccer_vision {
namespace {

const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kCarpet(206, 232, 210);  // pale green
const cv::Scalar kGoal(110, 110, 110);
const cv::Scalar kKeyColor(90, 90, 90);  // legend keys for line styles
const cv::Scalar kMedianColor(70, 70, 70);
const cv::Scalar kP99Color(40, 40, 200);  // red
const cv::Scalar kRmsColor(30, 30, 140);  // dark red

cv::Scalar fromRgb(int r, int g, int b) {
  return {static_cast<double>(b), static_cast<double>(g), static_cast<double>(r)};
}

// Number in a legend: about three significant digits, no exponent for the usual magnitudes.
std::string number(double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[32];
  const double a = std::abs(v);
  if (a >= 1 || a == 0)
    std::snprintf(buf, sizeof buf, a >= 100 ? "%.0f" : (a >= 10 ? "%.1f" : "%.2f"), v);
  else
    std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

double earliest(std::initializer_list<const std::vector<double>*> times) {
  double t0 = std::numeric_limits<double>::infinity();
  for (const auto* t : times)
    for (double v : *t)
      if (std::isfinite(v)) t0 = std::min(t0, v);
  return std::isfinite(t0) ? t0 : 0.0;
}

std::vector<double> shifted(const std::vector<double>& t, double t0) {
  std::vector<double> out(t.size());
  std::transform(t.begin(), t.end(), out.begin(), [t0](double v) { return v - t0; });
  return out;
}

size_t finiteCount(const std::vector<double>& v) {
  return static_cast<size_t>(std::count_if(v.begin(), v.end(), [](double x) { return std::isfinite(x); }));
}

void requireLength(const std::string& where, const std::string& name, size_t got, size_t expected) {
  if (got != expected)
    throw std::invalid_argument(where + ": " + name + " has " + std::to_string(got) + " values, t has " +
                                std::to_string(expected));
}

// Panels laid out row by row under a title band.
cv::Mat composeFigure(const std::string& title, const std::vector<PlotCanvas>& panels, int columns) {
  constexpr int kHeader = 44;
  const int rows = (static_cast<int>(panels.size()) + columns - 1) / columns;
  const int pw = panels.front().width(), ph = panels.front().height();
  cv::Mat figure(kHeader + rows * ph, columns * pw, CV_8UC3, kWhite);
  int base = 0;
  double scale = 0.8;
  cv::Size ts = cv::getTextSize(title, cv::FONT_HERSHEY_SIMPLEX, scale, 2, &base);
  if (ts.width > figure.cols - 20) {
    scale *= (figure.cols - 20.0) / ts.width;
    ts = cv::getTextSize(title, cv::FONT_HERSHEY_SIMPLEX, scale, 2, &base);
  }
  cv::putText(figure, title, {(figure.cols - ts.width) / 2, 30}, cv::FONT_HERSHEY_SIMPLEX, scale,
              cv::Scalar(40, 40, 40), 2, cv::LINE_AA);
  for (size_t i = 0; i < panels.size(); ++i) {
    const int row = static_cast<int>(i) / columns, column = static_cast<int>(i) % columns;
    cv::Mat cell = figure(cv::Rect(column * pw, kHeader + row * ph, pw, ph));
    panels[i].renderInto(cell);
  }
  return figure;
}

std::string counted(size_t n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

std::string ordinal(int n) {
  const int tens = n % 100, units = n % 10;
  const char* suffix = (tens >= 11 && tens <= 13) ? "th"
                       : units == 1               ? "st"
                       : units == 2               ? "nd"
                       : units == 3               ? "rd"
                                                  : "th";
  return std::to_string(n) + suffix;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

void drawField(PlotCanvas& c, const FieldGeometry& f) {
  const double cx = f.carpetHalfLength(), cy = f.carpetHalfWidth();
  c.addFilledPolygon({-cx, cx, cx, -cx}, {-cy, -cy, cy, cy}, kCarpet);
  for (const LineSegment& l : f.lines())
    c.addPolyline({l.a.x(), l.b.x()}, {l.a.y(), l.b.y()}, kWhite, "", LineStyle::Solid, 2);
  for (const CircleArc& a : f.circles()) {
    std::vector<double> xs, ys;
    for (const Eigen::Vector2d& p : a.points(96)) {
      xs.push_back(p.x());
      ys.push_back(p.y());
    }
    c.addPolyline(xs, ys, kWhite, "", LineStyle::Solid, 2);
  }
  const double gw = f.goal_width / 2;
  for (double side : {-1.0, 1.0}) {
    const double mouth = side * f.halfLength(), back = side * (f.halfLength() + f.goal_depth);
    c.addPolyline({mouth, back, back, mouth}, {-gw, -gw, gw, gw}, kGoal, "", LineStyle::Solid, 3);
  }
}

}  // namespace

cv::Scalar trajectoryColor(const std::string& team, int index) {
  static const std::vector<cv::Scalar> blue = {
      fromRgb(31, 119, 180), fromRgb(8, 48, 107),   fromRgb(23, 160, 200), fromRgb(106, 61, 154),
      fromRgb(79, 111, 208), fromRgb(14, 124, 123), fromRgb(58, 95, 143),  fromRgb(140, 107, 177)};
  static const std::vector<cv::Scalar> yellow = {
      fromRgb(217, 160, 0), fromRgb(179, 88, 6),  fromRgb(140, 109, 0), fromRgb(230, 97, 1),
      fromRgb(200, 180, 0), fromRgb(160, 82, 45), fromRgb(192, 138, 0), fromRgb(127, 59, 8)};
  static const std::vector<cv::Scalar> other = {
      fromRgb(214, 39, 40),  fromRgb(227, 119, 194), fromRgb(50, 50, 50),    fromRgb(140, 86, 75),
      fromRgb(188, 189, 34), fromRgb(44, 160, 44),   fromRgb(127, 127, 127), fromRgb(255, 127, 14)};
  const std::string t = lower(team);
  const std::vector<cv::Scalar>& palette = t == "blue" ? blue : (t == "yellow" ? yellow : other);
  const int n = static_cast<int>(palette.size());
  return palette[static_cast<size_t>(((index % n) + n) % n)];
}

cv::Scalar truthShade(const cv::Scalar& c) {
  const double keep = 0.45;  // of the colour; the rest is white
  return {255 - keep * (255 - c[0]), 255 - keep * (255 - c[1]), 255 - keep * (255 - c[2])};
}

cv::Scalar robotErrorColor() { return fromRgb(31, 119, 180); }
cv::Scalar ballErrorColor() { return fromRgb(230, 85, 13); }
cv::Scalar predictionErrorColor() { return fromRgb(214, 39, 40); }

cv::Scalar stageColor(int i) {
  static const std::vector<cv::Scalar> palette = {
      fromRgb(31, 119, 180),  fromRgb(255, 127, 14), fromRgb(44, 160, 44),
      fromRgb(148, 103, 189), fromRgb(140, 86, 75),  fromRgb(227, 119, 194),
      fromRgb(127, 127, 127), fromRgb(188, 189, 34), fromRgb(23, 190, 207)};
  const int n = static_cast<int>(palette.size());
  return palette[static_cast<size_t>(((i % n) + n) % n)];
}

// ---------------------------------------------------------------------------------------
cv::Mat renderTrajectories(const std::vector<TrajectorySeries>& series, const FieldGeometry& field) {
  size_t points = 0;
  for (const TrajectorySeries& s : series) {
    const std::string where = "trajectory plot, series '" + s.label + "'";
    requireLength(where, "truth_x", s.truth_x.size(), s.t.size());
    requireLength(where, "truth_y", s.truth_y.size(), s.t.size());
    requireLength(where, "tracked_x", s.tracked_x.size(), s.t.size());
    requireLength(where, "tracked_y", s.tracked_y.size(), s.t.size());
    for (size_t i = 0; i < s.t.size(); ++i)
      points += (std::isfinite(s.truth_x[i]) && std::isfinite(s.truth_y[i])) +
                (std::isfinite(s.tracked_x[i]) && std::isfinite(s.tracked_y[i]));
  }
  double t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
  for (const TrajectorySeries& s : series)
    for (double t : s.t)
      if (std::isfinite(t)) t_lo = std::min(t_lo, t), t_hi = std::max(t_hi, t);

  PlotCanvas c(1300, 800);
  std::string title = "Ground truth vs tracked trajectories";
  if (!series.empty()) title += " (" + std::to_string(series.size()) + " targets";
  if (!series.empty() && t_hi >= t_lo) title += ", " + number(t_hi - t_lo) + " s";
  if (!series.empty()) title += ")";
  c.setTitle(title);
  // Axes fixed to the carpet: one wild position must not shrink the field to a dot.
  const double margin = 0.2, x_end = field.carpetHalfLength() + margin,
               y_end = field.carpetHalfWidth() + margin;
  c.setXRange(-x_end, x_end);
  c.setYRange(-y_end, y_end);
  size_t off_field = 0;
  for (const TrajectorySeries& s : series)
    for (size_t i = 0; i < s.t.size(); ++i) {
      for (auto [x, y] : {std::pair{s.truth_x[i], s.truth_y[i]}, std::pair{s.tracked_x[i], s.tracked_y[i]}})
        if (std::isfinite(x) && std::isfinite(y) && !field.onCarpet(x, y, margin)) ++off_field;
    }
  c.setXLabel(off_field == 0
                  ? "x [m]"
                  : "x [m]; " + counted(off_field, "position", "positions") + " beyond the carpet not shown");
  c.setYLabel("y [m]");
  c.setEqualAspect(true);
  c.setLegendPosition(LegendPosition::OutsideRight);
  drawField(c, field);
  if (points == 0) c.setNote("no data");

  std::vector<int> per_team_index;
  std::vector<std::string> teams;
  for (const TrajectorySeries& s : series) {
    const std::string team = lower(s.team);
    auto it = std::find(teams.begin(), teams.end(), team);
    if (it == teams.end()) {
      teams.push_back(team);
      per_team_index.push_back(0);
      it = teams.end() - 1;
    }
    const cv::Scalar color = trajectoryColor(team, per_team_index[static_cast<size_t>(it - teams.begin())]++);
    c.addPolyline(s.truth_x, s.truth_y, truthShade(color), "", LineStyle::Solid, 6);
    c.addPolyline(s.tracked_x, s.tracked_y, color, "", LineStyle::Dashed, 2);
    c.addLegendEntry(s.label, color, LineStyle::Solid, 3);
    // Where the target ended, with its name, so the lines can be told apart without the legend.
    for (size_t i = s.t.size(); i-- > 0;) {
      if (!std::isfinite(s.truth_x[i]) || !std::isfinite(s.truth_y[i])) continue;
      c.addScatter({s.truth_x[i]}, {s.truth_y[i]}, color, "", 4);
      c.addText(s.truth_x[i] + 0.1, s.truth_y[i], s.label, color * 0.8, 0.42);
      break;
    }
  }
  c.addLegendEntry("ground truth", truthShade(kKeyColor), LineStyle::Solid, 6);
  c.addLegendEntry("tracked", kKeyColor, LineStyle::Dashed, 2);
  return c.render();
}

void plotTrajectories(const std::vector<TrajectorySeries>& series, const FieldGeometry& field,
                      const std::string& png_path) {
  writePng(renderTrajectories(series, field), png_path);
}

// ---------------------------------------------------------------------------------------
cv::Mat renderPositionError(const ErrorSeries& e) {
  const std::string where = "position error plot";
  if (!e.robot_error_mm.empty()) requireLength(where, "robot_error_mm", e.robot_error_mm.size(), e.t.size());
  if (!e.ball_error_mm.empty()) requireLength(where, "ball_error_mm", e.ball_error_mm.size(), e.t.size());
  const std::vector<double> t = shifted(e.t, earliest({&e.t}));

  PlotCanvas c(1000, 700);
  c.setTitle("Per-frame position error against ground truth");
  c.setXLabel("time [s]");
  c.setYLabel("position error [mm]");
  // Headroom above the largest error keeps the legend off the curves.
  double largest = 0;
  for (const auto* err : {&e.robot_error_mm, &e.ball_error_mm})
    for (double v : *err)
      if (std::isfinite(v)) largest = std::max(largest, v);
  c.setYRange(0, largest > 0 ? 1.22 * largest : std::numeric_limits<double>::quiet_NaN());
  auto add = [&](const std::vector<double>& err, const cv::Scalar& color, const std::string& name) {
    if (err.empty()) return;
    std::string label = name + ": ";
    const size_t n = finiteCount(err);
    if (n == 0) {
      label += "never matched";
    } else {
      label += "RMS " + number(rootMeanSquare(err)) + " mm, p95 " + number(percentile(err, 95)) + " mm, " +
               counted(n, "frame", "frames");
    }
    c.addPolyline(t, err, color, label, LineStyle::Solid, 1);
  };
  add(e.robot_error_mm, robotErrorColor(), "robots");
  add(e.ball_error_mm, ballErrorColor(), "ball");
  return c.render();
}

void plotPositionError(const ErrorSeries& errors, const std::string& png_path) {
  writePng(renderPositionError(errors), png_path);
}

// ---------------------------------------------------------------------------------------
cv::Mat renderStageTimingHistogram(const StageTimes& times) {
  if (times.stage.size() != times.ms.size())
    throw std::invalid_argument("stage timing plot: " + std::to_string(times.stage.size()) +
                                " stage names but " + std::to_string(times.ms.size()) + " time series");
  const std::string title = "Processing time per frame and stage";
  if (times.stage.empty()) {
    PlotCanvas c(1000, 700);
    c.setTitle(title);
    c.setXLabel("time [ms]");
    c.setYLabel("frames");
    return c.render();
  }
  const int n = static_cast<int>(times.stage.size());
  const int columns = n == 1 ? 1 : (n <= 4 ? 2 : 3);
  const int rows = (n + columns - 1) / columns;
  const int pw = columns == 1 ? 1000 : (columns == 2 ? 500 : 400), ph = rows == 1 ? 656 : 330;

  std::vector<PlotCanvas> panels;
  for (int i = 0; i < n; ++i) {
    const std::vector<double> v = finiteValues(times.ms[static_cast<size_t>(i)]);
    PlotCanvas c(pw, ph);
    c.setTitle(times.stage[static_cast<size_t>(i)] + " (" + counted(v.size(), "frame", "frames") + ")");
    c.setXLabel("time [ms]");
    c.setYLabel("frames");
    c.setYRange(0, std::numeric_limits<double>::quiet_NaN());
    if (!v.empty()) {
      const double p50 = percentile(v, 50), p99 = percentile(v, 99);
      const auto [min_it, max_it] = std::minmax_element(v.begin(), v.end());
      double lo = *min_it, hi = *max_it;
      // A few hiccups far out would squeeze the histogram into one bar: values beyond
      // 2·p99 are left out of the axis and counted in the legend instead.
      const double cut = 2 * p99;
      const bool tail_cut = p99 > 0 && hi > cut && cut > lo;
      if (tail_cut) {
        hi = lo;
        for (double x : v)
          if (x <= cut) hi = std::max(hi, x);
      }
      // Rice rule for the bin count, within bounds that keep bars readable; one bar centred
      // on the value when all times are the same.
      int bins =
          std::clamp(static_cast<int>(std::lround(2 * std::cbrt(static_cast<double>(v.size())))), 8, 40);
      if (hi - lo <= 1e-9 * std::max(1.0, std::abs(hi))) {
        const double half = std::max(0.05 * std::abs(lo), 0.001);
        lo -= half;
        hi += half;
        bins = 1;
      }
      std::vector<double> edges(static_cast<size_t>(bins) + 1), counts(static_cast<size_t>(bins), 0.0);
      for (int b = 0; b <= bins; ++b) edges[static_cast<size_t>(b)] = lo + (hi - lo) * b / bins;
      long above = 0;
      for (double x : v) {
        if (x > hi) {
          ++above;
          continue;
        }
        const int b = std::min(bins - 1, static_cast<int>((x - lo) / (hi - lo) * bins));
        counts[static_cast<size_t>(std::max(0, b))] += 1;
      }
      const double top = *std::max_element(counts.begin(), counts.end()) * 1.35;  // legend room
      c.setYRange(0, top);
      c.addBars(edges, counts, stageColor(i));
      c.addPolyline({p50, p50}, {0, top}, kMedianColor, "p50 " + number(p50) + " ms", LineStyle::Dashed, 2);
      c.addPolyline({p99, p99}, {0, top}, kP99Color, "p99 " + number(p99) + " ms", LineStyle::Dashed, 2);
      if (tail_cut)
        c.setXLabel("time [ms]; " + counted(static_cast<size_t>(above), "frame", "frames") + " > " +
                    number(cut) + " ms not shown (max " + number(*max_it) + ")");
    }
    panels.push_back(c);
  }
  return composeFigure(title, panels, columns);
}

void plotStageTimingHistogram(const StageTimes& times, const std::string& png_path) {
  writePng(renderStageTimingHistogram(times), png_path);
}

// ---------------------------------------------------------------------------------------
cv::Mat renderPredictionError(const std::vector<PredictionErrorSeries>& series) {
  for (const PredictionErrorSeries& s : series) {
    if (s.frame_step < 1)
      throw std::invalid_argument("prediction error plot: frame_step must be >= 1 (got " +
                                  std::to_string(s.frame_step) + ")");
    requireLength("prediction error plot, frame step " + std::to_string(s.frame_step), "error_mm",
                  s.error_mm.size(), s.t.size());
  }
  const std::string title = "Kalman prediction error vs frame step";
  if (series.empty()) {
    PlotCanvas c(1000, 700);
    c.setTitle(title);
    c.setXLabel("time [s]");
    c.setYLabel("prediction error [mm]");
    return c.render();
  }
  std::vector<const PredictionErrorSeries*> sorted;
  for (const PredictionErrorSeries& s : series) sorted.push_back(&s);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto* a, const auto* b) { return a->frame_step < b->frame_step; });

  // Shared axes: the same error on every panel is the same height.
  double t0 = std::numeric_limits<double>::infinity(), t1 = -t0, e_max = 0;
  for (const auto* s : sorted) {
    for (size_t i = 0; i < s->t.size(); ++i) {
      if (!std::isfinite(s->t[i]) || !std::isfinite(s->error_mm[i])) continue;
      t0 = std::min(t0, s->t[i]);
      t1 = std::max(t1, s->t[i]);
      e_max = std::max(e_max, s->error_mm[i]);
    }
  }
  const bool any = t1 >= t0;
  const int n = static_cast<int>(sorted.size());
  const int columns = n == 1 ? 1 : 2;
  const int rows = (n + columns - 1) / columns;
  const int pw = columns == 1 ? 1000 : 500, ph = rows == 1 ? 656 : 330;

  std::string summary_rms, summary_steps;
  std::vector<PlotCanvas> panels;
  for (const auto* s : sorted) {
    const double rms = rootMeanSquare(s->error_mm);
    const size_t predictions = finiteCount(s->error_mm);
    PlotCanvas c(pw, ph);
    const std::string step = std::to_string(s->frame_step);
    c.setTitle("frame step " + step +
               (s->frame_step == 1 ? " (every frame)" : " (every " + ordinal(s->frame_step) + " frame)"));
    c.setXLabel("time [s]");
    c.setYLabel("prediction error [mm]");
    if (any) {
      c.setXRange(0, t1 > t0 ? t1 - t0 : std::numeric_limits<double>::quiet_NaN());
      c.setYRange(0, e_max > 0 ? e_max * 1.35 : std::numeric_limits<double>::quiet_NaN());  // legend room
    } else {
      c.setYRange(0, std::numeric_limits<double>::quiet_NaN());
    }
    c.addPolyline(shifted(s->t, any ? t0 : 0.0), s->error_mm, predictionErrorColor(),
                  counted(predictions, "prediction", "predictions"), LineStyle::Solid, 1);
    if (predictions > 0) {
      c.addPolyline({0, any ? t1 - t0 : 1.0}, {rms, rms}, kRmsColor, "RMS " + number(rms) + " mm",
                    LineStyle::Dashed, 2);
      summary_rms += (summary_rms.empty() ? "" : " / ") + number(rms);
      summary_steps += (summary_steps.empty() ? "" : " / ") + step;
    }
    panels.push_back(c);
  }
  const bool several = summary_steps.find('/') != std::string::npos;
  return composeFigure(summary_rms.empty() ? title
                                           : title + ": RMS " + summary_rms + " mm at step" +
                                                 (several ? "s " : " ") + summary_steps,
                       panels, columns);
}

void plotPredictionError(const std::vector<PredictionErrorSeries>& series, const std::string& png_path) {
  writePng(renderPredictionError(series), png_path);
}

}  // namespace soccer_vision
