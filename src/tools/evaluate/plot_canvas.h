// A small chart drawn with OpenCV only (no plotting library): data-space axes with "nice"
// ticks, polylines, scatter points, histogram bars and a legend, rendered anti-aliased on a
// white background. Used by the evaluation figures (evaluation_plots.h).
//
// Data are plain doubles; NaN and inf are skipped (a polyline breaks at them). A chart with
// no finite data renders as axes with a "no data" note instead of failing.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace soccer_vision {

// Tick values k·step inside [lo, hi] (ends inclusive), step = 1, 2 or 5 × 10^n, the smallest
// such step that gives at most max_ticks ticks. lo > hi is swapped; a zero-width range
// v..v is widened to v ± max(5 % of |v|, 0.5) first. Throws std::invalid_argument for
// non-finite ends or max_ticks < 2.
std::vector<double> niceTicks(double lo, double hi, int max_ticks = 8);

// The step niceTicks would use (same rules).
double niceTickStep(double lo, double hi, int max_ticks = 8);

// A tick label with as many decimals as the step needs (step 0.2: "1.4"; step 2: "4"),
// exponent notation for magnitudes >= 1e6 or steps below 1e-5; never "-0".
std::string formatTick(double value, double step);

enum class LineStyle { Solid, Dashed, Dotted };

enum class LegendPosition { TopRight, TopLeft, BottomRight, BottomLeft, OutsideRight, None };

// Colours are OpenCV BGR scalars.
class PlotCanvas {
 public:
  PlotCanvas(int width_px = 1000, int height_px = 700);  // throws std::invalid_argument if < 200×150

  void setTitle(const std::string& title) { title_ = title; }
  void setXLabel(const std::string& label) { x_label_ = label; }
  void setYLabel(const std::string& label) { y_label_ = label; }
  // Fixed axis ends; NaN leaves that end to autoscaling (e.g. setYRange(0, NaN)).
  void setXRange(double lo, double hi);
  void setYRange(double lo, double hi);
  // Same metres per pixel on both axes (field plots); the shorter range is widened.
  void setEqualAspect(bool equal) { equal_aspect_ = equal; }
  void setLegendPosition(LegendPosition p) { legend_position_ = p; }
  void setGrid(bool grid) { grid_ = grid; }
  // A grey note centred on the plot area. Without one, a chart with no finite data says
  // "no data"; a chart whose data are only decoration (a field outline) sets it itself.
  void setNote(const std::string& note) { note_ = note; }

  // xs and ys must have the same length (std::invalid_argument otherwise). An empty label
  // keeps the series out of the legend.
  void addPolyline(const std::vector<double>& xs, const std::vector<double>& ys, const cv::Scalar& color,
                   const std::string& label = "", LineStyle style = LineStyle::Solid, int thickness = 2);
  void addScatter(const std::vector<double>& xs, const std::vector<double>& ys, const cv::Scalar& color,
                  const std::string& label = "", int radius = 3);
  // Bars over bins [edges[i], edges[i+1]) of height counts[i] (edges.size() == counts.size() + 1).
  void addBars(const std::vector<double>& edges, const std::vector<double>& counts, const cv::Scalar& color,
               const std::string& label = "");
  // A filled polygon (e.g. the carpet of a field plot), drawn in insertion order.
  void addFilledPolygon(const std::vector<double>& xs, const std::vector<double>& ys, const cv::Scalar& color,
                        const std::string& label = "");
  // A text annotation whose left end sits at (x, y) (skipped when not finite).
  void addText(double x, double y, const std::string& text, const cv::Scalar& color, double scale = 0.45);
  // A legend line without data (e.g. "p99 2.1 ms" or a style key).
  void addLegendEntry(const std::string& label, const cv::Scalar& color, LineStyle style = LineStyle::Solid,
                      int thickness = 2);

  int width() const { return width_; }
  int height() const { return height_; }
  bool hasData() const;  // any finite point or bar

  // The chart as a width()×height() BGR image.
  cv::Mat render() const;
  // Draws the chart onto target (CV_8UC3 of exactly width()×height(), e.g. a ROI of a
  // larger figure); throws std::invalid_argument otherwise.
  void renderInto(cv::Mat& target) const;

  // Where the data point (x, y) lands in the rendered image (sub-pixel, pixel centres at
  // integers), and the plot area; both follow the same layout as render().
  cv::Point2d toPixel(double x, double y) const;
  cv::Rect plotArea() const;
  // The axis ranges render() uses (after autoscaling, tick rounding and equal aspect).
  cv::Vec2d xRange() const;
  cv::Vec2d yRange() const;

 private:
  struct Series {
    enum class Kind { Polyline, Scatter, Bars, Polygon, Text, LegendOnly } kind;
    std::vector<double> xs, ys;  // bars: xs = edges, ys = counts
    cv::Scalar color;
    std::string label;
    LineStyle style = LineStyle::Solid;
    int size = 2;      // thickness or radius
    std::string text;  // Text
    double scale = 0;  // Text font scale
  };
  struct Layout {
    cv::Rect plot;
    double x_lo, x_hi, y_lo, y_hi;
    std::vector<double> x_ticks, y_ticks;
    double x_step, y_step;
    cv::Rect legend;  // empty: no legend
  };

  Layout layout() const;
  void dataBounds(double& x_lo, double& x_hi, double& y_lo, double& y_hi) const;
  cv::Size legendSize() const;
  void drawAxes(cv::Mat& img, const Layout& l) const;
  void drawSeries(cv::Mat& img, const Layout& l) const;
  void drawLegend(cv::Mat& img, const Layout& l) const;

  int width_, height_;
  std::string title_, x_label_, y_label_, note_;
  double x_fixed_lo_, x_fixed_hi_, y_fixed_lo_, y_fixed_hi_;
  bool equal_aspect_ = false;
  bool grid_ = true;
  LegendPosition legend_position_ = LegendPosition::TopRight;
  std::vector<Series> series_;
};

// Writes img as a PNG; throws std::runtime_error naming the path when it cannot (missing
// directory, no write permission, a name that does not end in ".png").
void writePng(const cv::Mat& img, const std::string& png_path);

}  // namespace soccer_vision
