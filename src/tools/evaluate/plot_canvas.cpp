#include "plot_canvas.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace soccer_vision {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTickScale = 0.5;
constexpr double kAxisLabelScale = 0.6;
constexpr double kTitleScale = 0.7;
constexpr double kLegendScale = 0.5;
constexpr double kNoteScale = 1.0;
const cv::Scalar kTextColor(40, 40, 40);
const cv::Scalar kFrameColor(90, 90, 90);
const cv::Scalar kGridColor(228, 228, 228);
const cv::Scalar kNoteColor(150, 150, 150);
const cv::Scalar kLegendBorder(190, 190, 190);
const cv::Scalar kWhite(255, 255, 255);

// OpenCV's drawing calls take fixed-point coordinates with this many fractional bits: lines
// land where the data say, not on the nearest whole pixel.
constexpr int kShift = 4;
constexpr double kSubPixel = 1 << kShift;

constexpr int kLegendRow = 22, kLegendPad = 8, kLegendSample = 34, kLegendGap = 8, kLegendColumnGap = 16;

double notANumber() { return std::numeric_limits<double>::quiet_NaN(); }

void normaliseRange(double& lo, double& hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi))
    throw std::invalid_argument("plot: axis range ends must be finite");
  if (lo > hi) std::swap(lo, hi);
  if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    const double centre = 0.5 * (lo + hi), half = std::max(0.05 * std::abs(centre), 0.5);
    lo = centre - half;
    hi = centre + half;
  }
}

// Multiples of step inside [lo, hi]: the first multiplier and the count (tolerant to rounding).
double firstMultiple(double lo, double step) { return std::ceil(lo / step - 1e-9); }
long tickCount(double lo, double hi, double step) {
  return static_cast<long>(std::floor(hi / step + 1e-9) - firstMultiple(lo, step)) + 1;
}

cv::Point toFixed(const cv::Point2d& p) {
  return {static_cast<int>(std::lround(p.x * kSubPixel)), static_cast<int>(std::lround(p.y * kSubPixel))};
}

// Liang–Barsky: clips segment a-b to the rectangle [x0, x1] × [y0, y1]; false if outside.
bool clipSegment(cv::Point2d& a, cv::Point2d& b, double x0, double y0, double x1, double y1) {
  double t0 = 0, t1 = 1;
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x - x0, x1 - a.x, a.y - y0, y1 - a.y};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  const cv::Point2d start = a;
  a = start + t0 * cv::Point2d(dx, dy);
  b = start + t1 * cv::Point2d(dx, dy);
  return true;
}

void drawSegment(cv::Mat& img, const cv::Point2d& a, const cv::Point2d& b, const cv::Scalar& color,
                 int thickness) {
  cv::line(img, toFixed(a), toFixed(b), color, thickness, cv::LINE_AA, kShift);
}

// One unbroken run of a polyline in pixel coordinates of img; dash phase carries over the
// vertices so a dashed curve made of many short segments still shows dashes.
void drawRun(cv::Mat& img, const std::vector<cv::Point2d>& run, const cv::Scalar& color, int thickness,
             LineStyle style) {
  const double margin = 8.0 + thickness;
  const double x0 = -margin, y0 = -margin, x1 = img.cols - 1 + margin, y1 = img.rows - 1 + margin;
  if (run.size() == 1) {  // an isolated point between gaps: a dot a little wider than the line
    const cv::Point2d& p = run.front();
    if (p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1)
      cv::circle(img, toFixed(p), static_cast<int>(std::max(2.0, 1.0 * thickness) * kSubPixel), color,
                 cv::FILLED, cv::LINE_AA, kShift);
    return;
  }
  const double on = style == LineStyle::Dashed ? 10.0 : 1.0;
  const double off = style == LineStyle::Dashed ? 7.0 : 4.0 + thickness;
  const double period = on + off;
  double phase = 0;
  for (size_t i = 1; i < run.size(); ++i) {
    cv::Point2d a = run[i - 1], b = run[i];
    if (!clipSegment(a, b, x0, y0, x1, y1)) continue;
    if (style == LineStyle::Solid) {
      drawSegment(img, a, b, color, thickness);
      continue;
    }
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    if (length <= 0) continue;
    const cv::Point2d dir = (b - a) / length;
    double pos = 0;
    while (pos < length) {
      const double in_period = std::fmod(phase + pos, period);
      if (in_period < on) {
        const double end = std::min(length, pos + on - in_period);
        drawSegment(img, a + pos * dir, a + end * dir, color, thickness);
        pos = end;
      } else {
        pos = std::min(length, pos + period - in_period);
      }
    }
    phase += length;
  }
}

cv::Scalar darker(const cv::Scalar& c, double f = 0.7) { return {c[0] * f, c[1] * f, c[2] * f}; }

// Font scale at which text fits into max_width (never above scale).
double fittingScale(const std::string& text, double scale, int thickness, int max_width) {
  int base = 0;
  const int w = cv::getTextSize(text, kFont, scale, thickness, &base).width;
  return w > max_width && w > 0 ? std::max(0.3, scale * max_width / w) : scale;
}

void putCentred(cv::Mat& img, const std::string& text, cv::Point centre_baseline, double scale,
                const cv::Scalar& color, int thickness) {
  int base = 0;
  const cv::Size s = cv::getTextSize(text, kFont, scale, thickness, &base);
  cv::putText(img, text, {centre_baseline.x - s.width / 2, centre_baseline.y}, kFont, scale, color, thickness,
              cv::LINE_AA);
}

// Text turned 90° counter-clockwise (a y-axis title), its centre at `centre`. Drawn black on
// white into a scratch image, rotated, then darkened into img so it never erases lines.
void putVertical(cv::Mat& img, const std::string& text, cv::Point centre, double scale) {
  int base = 0;
  const cv::Size s = cv::getTextSize(text, kFont, scale, 1, &base);
  cv::Mat flat(s.height + base + 4, s.width + 4, CV_8UC3, kWhite);
  cv::putText(flat, text, {2, s.height + 2}, kFont, scale, kTextColor, 1, cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(flat, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect where(centre.x - turned.cols / 2, centre.y - turned.rows / 2, turned.cols, turned.rows);
  const cv::Rect visible = where & cv::Rect(0, 0, img.cols, img.rows);
  if (visible.empty()) return;
  cv::Mat target = img(visible);
  cv::min(target, turned(visible - where.tl()), target);
}

bool finitePair(double x, double y) { return std::isfinite(x) && std::isfinite(y); }

}  // namespace

std::vector<double> niceTicks(double lo, double hi, int max_ticks) {
  const double step = niceTickStep(lo, hi, max_ticks);
  normaliseRange(lo, hi);
  const double first = firstMultiple(lo, step);
  const long n = tickCount(lo, hi, step);
  std::vector<double> ticks;
  ticks.reserve(static_cast<size_t>(std::max(0L, n)));
  for (long i = 0; i < n; ++i) {
    const double v = (first + static_cast<double>(i)) * step;
    ticks.push_back(std::abs(v) < 1e-9 * step ? 0.0 : v);
  }
  return ticks;
}

double niceTickStep(double lo, double hi, int max_ticks) {
  if (max_ticks < 2)
    throw std::invalid_argument("niceTicks: max_ticks must be >= 2 (got " + std::to_string(max_ticks) + ")");
  normaliseRange(lo, hi);
  const double raw = (hi - lo) / (max_ticks - 1);
  // Start a decade below the raw step: alignment can let a slightly smaller step fit.
  const int first_exponent = static_cast<int>(std::floor(std::log10(raw))) - 1;
  for (int e = first_exponent; e < first_exponent + 4; ++e) {
    const double decade = std::pow(10.0, e);
    for (double m : {1.0, 2.0, 5.0}) {
      const double step = m * decade;
      if (tickCount(lo, hi, step) <= max_ticks) return step;
    }
  }
  return std::pow(10.0, first_exponent + 4);  // not reached: one step over the range fits
}

std::string formatTick(double value, double step) {
  char buf[64];
  if (!std::isfinite(value)) return std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
  step = std::abs(step);
  if (!std::isfinite(step) || step == 0) {
    std::snprintf(buf, sizeof buf, "%g", value);
    return buf;
  }
  if (std::abs(value) < 1e-6 * step) return "0";
  int decimals = 0;
  for (double scaled = step; decimals < 15; ++decimals, scaled *= 10)
    if (std::abs(scaled - std::round(scaled)) <= 1e-6 * scaled) break;
  if (decimals > 5 || std::abs(value) >= 1e6) {
    const int digits =
        static_cast<int>(std::floor(std::log10(std::abs(value))) - std::floor(std::log10(step))) + 1;
    std::snprintf(buf, sizeof buf, "%.*g", std::clamp(digits, 1, 15), value);
  } else {
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  }
  return buf;
}

PlotCanvas::PlotCanvas(int width_px, int height_px)
    : width_(width_px),
      height_(height_px),
      x_fixed_lo_(notANumber()),
      x_fixed_hi_(notANumber()),
      y_fixed_lo_(notANumber()),
      y_fixed_hi_(notANumber()) {
  if (width_px < 200 || height_px < 150)
    throw std::invalid_argument("PlotCanvas: size " + std::to_string(width_px) + "x" +
                                std::to_string(height_px) + " is below 200x150");
}

namespace {
void checkFixedRange(const char* axis, double lo, double hi) {
  if (std::isinf(lo) || std::isinf(hi))
    throw std::invalid_argument(std::string("PlotCanvas: ") + axis + " range must not be infinite");
  if (!std::isnan(lo) && !std::isnan(hi) && lo >= hi)
    throw std::invalid_argument(std::string("PlotCanvas: ") + axis + " range " + std::to_string(lo) + " .. " +
                                std::to_string(hi) + " is empty");
}
void checkSameLength(const char* what, size_t a, size_t b) {
  if (a != b)
    throw std::invalid_argument(std::string("PlotCanvas::") + what + ": " + std::to_string(a) +
                                " x values but " + std::to_string(b) + " y values");
}
}  // namespace

void PlotCanvas::setXRange(double lo, double hi) {
  checkFixedRange("x", lo, hi);
  x_fixed_lo_ = lo;
  x_fixed_hi_ = hi;
}

void PlotCanvas::setYRange(double lo, double hi) {
  checkFixedRange("y", lo, hi);
  y_fixed_lo_ = lo;
  y_fixed_hi_ = hi;
}

void PlotCanvas::addPolyline(const std::vector<double>& xs, const std::vector<double>& ys,
                             const cv::Scalar& color, const std::string& label, LineStyle style,
                             int thickness) {
  checkSameLength("addPolyline", xs.size(), ys.size());
  series_.push_back(
      {Series::Kind::Polyline, xs, ys, color, label, style, std::clamp(thickness, 1, 20), {}, 0});
}

void PlotCanvas::addScatter(const std::vector<double>& xs, const std::vector<double>& ys,
                            const cv::Scalar& color, const std::string& label, int radius) {
  checkSameLength("addScatter", xs.size(), ys.size());
  series_.push_back(
      {Series::Kind::Scatter, xs, ys, color, label, LineStyle::Solid, std::clamp(radius, 1, 30), {}, 0});
}

void PlotCanvas::addBars(const std::vector<double>& edges, const std::vector<double>& counts,
                         const cv::Scalar& color, const std::string& label) {
  if (edges.size() != counts.size() + 1)
    throw std::invalid_argument("PlotCanvas::addBars: " + std::to_string(counts.size()) + " bars need " +
                                std::to_string(counts.size() + 1) + " edges, got " +
                                std::to_string(edges.size()));
  series_.push_back({Series::Kind::Bars, edges, counts, color, label, LineStyle::Solid, 1, {}, 0});
}

void PlotCanvas::addFilledPolygon(const std::vector<double>& xs, const std::vector<double>& ys,
                                  const cv::Scalar& color, const std::string& label) {
  checkSameLength("addFilledPolygon", xs.size(), ys.size());
  series_.push_back({Series::Kind::Polygon, xs, ys, color, label, LineStyle::Solid, 1, {}, 0});
}

void PlotCanvas::addText(double x, double y, const std::string& text, const cv::Scalar& color, double scale) {
  series_.push_back(
      {Series::Kind::Text, {x}, {y}, color, "", LineStyle::Solid, 1, text, std::clamp(scale, 0.2, 3.0)});
}

void PlotCanvas::addLegendEntry(const std::string& label, const cv::Scalar& color, LineStyle style,
                                int thickness) {
  series_.push_back(
      {Series::Kind::LegendOnly, {}, {}, color, label, style, std::clamp(thickness, 1, 20), {}, 0});
}

bool PlotCanvas::hasData() const {
  for (const Series& s : series_) {
    if (s.kind == Series::Kind::Text || s.kind == Series::Kind::LegendOnly) continue;
    if (s.kind == Series::Kind::Bars) {
      for (size_t i = 0; i < s.ys.size(); ++i)
        if (std::isfinite(s.xs[i]) && std::isfinite(s.xs[i + 1]) && std::isfinite(s.ys[i])) return true;
      continue;
    }
    for (size_t i = 0; i < s.xs.size(); ++i)
      if (finitePair(s.xs[i], s.ys[i])) return true;
  }
  return false;
}

void PlotCanvas::dataBounds(double& x_lo, double& x_hi, double& y_lo, double& y_hi) const {
  x_lo = y_lo = std::numeric_limits<double>::infinity();
  x_hi = y_hi = -std::numeric_limits<double>::infinity();
  auto take = [&](double x, double y) {
    x_lo = std::min(x_lo, x);
    x_hi = std::max(x_hi, x);
    y_lo = std::min(y_lo, y);
    y_hi = std::max(y_hi, y);
  };
  for (const Series& s : series_) {
    if (s.kind == Series::Kind::Text || s.kind == Series::Kind::LegendOnly) continue;
    if (s.kind == Series::Kind::Bars) {
      for (size_t i = 0; i < s.ys.size(); ++i) {
        if (!std::isfinite(s.xs[i]) || !std::isfinite(s.xs[i + 1]) || !std::isfinite(s.ys[i])) continue;
        take(s.xs[i], 0.0);
        take(s.xs[i + 1], s.ys[i]);
      }
      continue;
    }
    for (size_t i = 0; i < s.xs.size(); ++i)
      if (finitePair(s.xs[i], s.ys[i])) take(s.xs[i], s.ys[i]);
  }
  if (x_lo > x_hi) x_lo = x_hi = y_lo = y_hi = notANumber();
}

namespace {

// One axis: fixed ends where given, data (padded by 4 %) elsewhere, never empty.
void resolveAxis(double fixed_lo, double fixed_hi, double data_lo, double data_hi, double& lo, double& hi) {
  const bool auto_lo = std::isnan(fixed_lo), auto_hi = std::isnan(fixed_hi);
  lo = auto_lo ? data_lo : fixed_lo;
  hi = auto_hi ? data_hi : fixed_hi;
  if (std::isnan(lo) && std::isnan(hi)) {
    lo = 0;
    hi = 1;
  } else if (std::isnan(lo)) {
    lo = hi - std::max(0.1 * std::abs(hi), 1.0);
  } else if (std::isnan(hi)) {
    hi = lo + std::max(0.1 * std::abs(lo), 1.0);
  }
  if (hi <= lo) {  // all data at one value, or a fixed end beyond the data
    if (auto_lo && auto_hi)
      normaliseRange(lo, hi);
    else if (auto_hi)
      hi = lo + std::max(0.1 * std::abs(lo), 1.0);
    else
      lo = hi - std::max(0.1 * std::abs(hi), 1.0);
  }
  const double pad = 0.04 * (hi - lo);
  if (auto_lo) lo -= pad;
  if (auto_hi) hi += pad;
}

int textWidth(const std::string& text, double scale) {
  int base = 0;
  return cv::getTextSize(text, kFont, scale, 1, &base).width;
}

}  // namespace

cv::Size PlotCanvas::legendSize() const {
  if (legend_position_ == LegendPosition::None) return {0, 0};
  int entries = 0, widest = 0;
  for (const Series& s : series_) {
    if (s.label.empty() || s.kind == Series::Kind::Text) continue;
    ++entries;
    widest = std::max(widest, textWidth(s.label, kLegendScale));
  }
  if (entries == 0) return {0, 0};
  const int available = height_ - 90;  // roughly the plot height
  const int rows_fit = std::max(1, (available - 2 * kLegendPad) / kLegendRow);
  const int columns = (entries + rows_fit - 1) / rows_fit;
  const int rows = (entries + columns - 1) / columns;
  const int column_width = kLegendSample + kLegendGap + widest;
  return {2 * kLegendPad + columns * column_width + (columns - 1) * kLegendColumnGap,
          2 * kLegendPad + rows * kLegendRow};
}

PlotCanvas::Layout PlotCanvas::layout() const {
  Layout l;
  const int top = title_.empty() ? 18 : 48;
  const int bottom = 34 + (x_label_.empty() ? 0 : 28);
  const cv::Size legend = legendSize();
  int right = 22;
  if (legend_position_ == LegendPosition::OutsideRight && legend.width > 0) right += legend.width + 4;
  const int y_title = y_label_.empty() ? 0 : 30;
  int left = 60 + y_title;

  double dx_lo, dx_hi, dy_lo, dy_hi;
  dataBounds(dx_lo, dx_hi, dy_lo, dy_hi);
  for (int pass = 0; pass < 3; ++pass) {
    l.plot = cv::Rect(left, top, std::max(20, width_ - left - right), std::max(20, height_ - top - bottom));
    resolveAxis(x_fixed_lo_, x_fixed_hi_, dx_lo, dx_hi, l.x_lo, l.x_hi);
    resolveAxis(y_fixed_lo_, y_fixed_hi_, dy_lo, dy_hi, l.y_lo, l.y_hi);
    if (equal_aspect_) {
      const double sx = (l.plot.width - 1) / (l.x_hi - l.x_lo), sy = (l.plot.height - 1) / (l.y_hi - l.y_lo);
      if (sx > sy) {
        const double centre = 0.5 * (l.x_lo + l.x_hi), half = 0.5 * (l.plot.width - 1) / sy;
        l.x_lo = centre - half;
        l.x_hi = centre + half;
      } else {
        const double centre = 0.5 * (l.y_lo + l.y_hi), half = 0.5 * (l.plot.height - 1) / sx;
        l.y_lo = centre - half;
        l.y_hi = centre + half;
      }
    }
    // x ticks: as many as fit without their labels touching.
    const double x_scale = (l.plot.width - 1) / (l.x_hi - l.x_lo);
    for (int max_ticks = std::max(3, l.plot.width / 70); max_ticks >= 2; --max_ticks) {
      l.x_step = niceTickStep(l.x_lo, l.x_hi, max_ticks);
      l.x_ticks = niceTicks(l.x_lo, l.x_hi, max_ticks);
      int widest = 0;
      for (double t : l.x_ticks) widest = std::max(widest, textWidth(formatTick(t, l.x_step), kTickScale));
      if (widest + 14 <= l.x_step * x_scale) break;
    }
    const int y_max_ticks = std::max(3, l.plot.height / 40);
    l.y_step = niceTickStep(l.y_lo, l.y_hi, y_max_ticks);
    l.y_ticks = niceTicks(l.y_lo, l.y_hi, y_max_ticks);
    int widest = 0;
    for (double t : l.y_ticks) widest = std::max(widest, textWidth(formatTick(t, l.y_step), kTickScale));
    const int needed = 10 + y_title + widest + 12;
    if (needed == left) break;
    left = needed;
  }

  l.legend = cv::Rect();
  if (legend.width > 0) {
    const cv::Rect& p = l.plot;
    const int inset = 10;
    cv::Point at;
    switch (legend_position_) {
      case LegendPosition::TopRight:
        at = {p.x + p.width - legend.width - inset, p.y + inset};
        break;
      case LegendPosition::TopLeft:
        at = {p.x + inset, p.y + inset};
        break;
      case LegendPosition::BottomRight:
        at = {p.x + p.width - legend.width - inset, p.y + p.height - legend.height - inset};
        break;
      case LegendPosition::BottomLeft:
        at = {p.x + inset, p.y + p.height - legend.height - inset};
        break;
      case LegendPosition::OutsideRight:
        at = {p.x + p.width + 12, p.y};
        break;
      case LegendPosition::None:
        break;
    }
    l.legend = cv::Rect(at, legend);
  }
  return l;
}

namespace {
struct Mapping {  // data -> pixel inside the plot area (origin at its top-left pixel)
  double x_lo, y_lo, sx, sy, bottom;
  cv::Point2d operator()(double x, double y) const { return {(x - x_lo) * sx, bottom - (y - y_lo) * sy}; }
};
Mapping mappingOf(const cv::Rect& plot, double x_lo, double x_hi, double y_lo, double y_hi) {
  return {x_lo, y_lo, (plot.width - 1) / (x_hi - x_lo), (plot.height - 1) / (y_hi - y_lo), plot.height - 1.0};
}
}  // namespace

cv::Point2d PlotCanvas::toPixel(double x, double y) const {
  const Layout l = layout();
  return mappingOf(l.plot, l.x_lo, l.x_hi, l.y_lo, l.y_hi)(x, y) + cv::Point2d(l.plot.x, l.plot.y);
}

cv::Rect PlotCanvas::plotArea() const { return layout().plot; }

cv::Vec2d PlotCanvas::xRange() const {
  const Layout l = layout();
  return {l.x_lo, l.x_hi};
}

cv::Vec2d PlotCanvas::yRange() const {
  const Layout l = layout();
  return {l.y_lo, l.y_hi};
}

cv::Mat PlotCanvas::render() const {
  cv::Mat img(height_, width_, CV_8UC3);
  renderInto(img);
  return img;
}

void PlotCanvas::renderInto(cv::Mat& target) const {
  if (target.type() != CV_8UC3 || target.cols != width_ || target.rows != height_)
    throw std::invalid_argument("PlotCanvas::renderInto: target must be CV_8UC3 of " +
                                std::to_string(width_) + "x" + std::to_string(height_));
  target.setTo(kWhite);
  const Layout l = layout();
  if (grid_) {
    const Mapping m = mappingOf(l.plot, l.x_lo, l.x_hi, l.y_lo, l.y_hi);
    cv::Mat area = target(l.plot);
    for (double t : l.x_ticks) {
      const double x = m(t, l.y_lo).x;
      drawSegment(area, {x, 0}, {x, l.plot.height - 1.0}, kGridColor, 1);
    }
    for (double t : l.y_ticks) {
      const double y = m(l.x_lo, t).y;
      drawSegment(area, {0, y}, {l.plot.width - 1.0, y}, kGridColor, 1);
    }
  }
  drawSeries(target, l);
  drawAxes(target, l);
  const std::string note = !note_.empty() ? note_ : (hasData() ? "" : "no data");
  if (!note.empty()) {
    const double scale = fittingScale(note, kNoteScale, 2, l.plot.width - 20);
    putCentred(target, note, {l.plot.x + l.plot.width / 2, l.plot.y + l.plot.height / 2 + 10}, scale,
               kNoteColor, 2);
  }
  drawLegend(target, l);
}

void PlotCanvas::drawSeries(cv::Mat& img, const Layout& l) const {
  cv::Mat area = img(l.plot);  // drawing into the plot area clips everything to it
  const Mapping m = mappingOf(l.plot, l.x_lo, l.x_hi, l.y_lo, l.y_hi);
  const double far = 1e5;  // pixels; keeps absurd coordinates out of OpenCV's fixed point
  auto clampPx = [far](cv::Point2d p) {
    return cv::Point2d(std::clamp(p.x, -far, far), std::clamp(p.y, -far, far));
  };
  for (const Series& s : series_) {
    switch (s.kind) {
      case Series::Kind::Polyline: {
        const double min_step = std::max(1.0, s.size / 3.0);
        std::vector<cv::Point2d> run;
        for (size_t i = 0; i <= s.xs.size(); ++i) {
          if (i < s.xs.size() && finitePair(s.xs[i], s.ys[i])) {
            // Points within a pixel (a third of the line width) of the last one kept add
            // nothing visible but drawing time (long runs at 60 Hz); a run's ends are kept.
            const cv::Point2d p = m(s.xs[i], s.ys[i]);
            const bool run_ends = i + 1 >= s.xs.size() || !finitePair(s.xs[i + 1], s.ys[i + 1]);
            if (!run.empty() && !run_ends && std::hypot(p.x - run.back().x, p.y - run.back().y) < min_step)
              continue;
            run.push_back(p);
            continue;
          }
          if (!run.empty()) drawRun(area, run, s.color, s.size, s.style);
          run.clear();
        }
        break;
      }
      case Series::Kind::Scatter:
        for (size_t i = 0; i < s.xs.size(); ++i) {
          if (!finitePair(s.xs[i], s.ys[i])) continue;
          const cv::Point2d p = m(s.xs[i], s.ys[i]);
          if (p.x < -s.size || p.y < -s.size || p.x > area.cols + s.size || p.y > area.rows + s.size)
            continue;
          cv::circle(area, toFixed(p), static_cast<int>(s.size * kSubPixel), s.color, cv::FILLED, cv::LINE_AA,
                     kShift);
        }
        break;
      case Series::Kind::Bars: {
        const double base = std::clamp(m(0, std::max(0.0, l.y_lo)).y, -1.0, area.rows + 1.0);
        for (size_t i = 0; i < s.ys.size(); ++i) {
          if (!std::isfinite(s.xs[i]) || !std::isfinite(s.xs[i + 1]) || !std::isfinite(s.ys[i]) ||
              s.ys[i] == 0)
            continue;
          const cv::Point2d a = clampPx(m(s.xs[i], s.ys[i])), b = clampPx(m(s.xs[i + 1], 0));
          const int x0 = static_cast<int>(std::lround(std::min(a.x, b.x)));
          const int x1 = std::max(x0, static_cast<int>(std::lround(std::max(a.x, b.x))) - 1);  // 1 px gap
          const int top = static_cast<int>(std::lround(std::min(a.y, base)));
          const int bottom = static_cast<int>(std::lround(std::max(a.y, base)));
          cv::rectangle(area, cv::Point(x0, top), cv::Point(x1, bottom), s.color, cv::FILLED);
          cv::rectangle(area, cv::Point(x0, top), cv::Point(x1, bottom), darker(s.color), 1);
        }
        break;
      }
      case Series::Kind::Polygon: {
        std::vector<cv::Point> corners;
        for (size_t i = 0; i < s.xs.size(); ++i)
          if (finitePair(s.xs[i], s.ys[i])) corners.push_back(toFixed(clampPx(m(s.xs[i], s.ys[i]))));
        if (corners.size() >= 3) {
          const std::vector<std::vector<cv::Point>> polygons{corners};
          cv::fillPoly(area, polygons, s.color, cv::LINE_AA, kShift);
        }
        break;
      }
      case Series::Kind::Text: {
        if (!finitePair(s.xs[0], s.ys[0])) break;
        const cv::Point2d p = clampPx(m(s.xs[0], s.ys[0]));
        int base = 0;
        const cv::Size ts = cv::getTextSize(s.text, kFont, s.scale, 1, &base);
        cv::putText(area, s.text, cv::Point(static_cast<int>(p.x), static_cast<int>(p.y) + ts.height / 2),
                    kFont, s.scale, s.color, 1, cv::LINE_AA);
        break;
      }
      case Series::Kind::LegendOnly:
        break;
    }
  }
}

void PlotCanvas::drawAxes(cv::Mat& img, const Layout& l) const {
  const cv::Rect& p = l.plot;
  const Mapping m = mappingOf(p, l.x_lo, l.x_hi, l.y_lo, l.y_hi);
  const cv::Point2d origin(p.x, p.y);
  cv::rectangle(img, cv::Point(p.x - 1, p.y - 1), cv::Point(p.x + p.width, p.y + p.height), kFrameColor, 1);
  int base = 0;
  for (double t : l.x_ticks) {
    const double x = m(t, l.y_lo).x + p.x;
    drawSegment(img, {x, p.y + p.height + 0.0}, {x, p.y + p.height + 5.0}, kFrameColor, 1);
    putCentred(img, formatTick(t, l.x_step), {static_cast<int>(std::lround(x)), p.y + p.height + 22},
               kTickScale, kTextColor, 1);
  }
  for (double t : l.y_ticks) {
    const double y = m(l.x_lo, t).y + p.y;
    drawSegment(img, {p.x - 6.0, y}, {p.x - 1.0, y}, kFrameColor, 1);
    const std::string label = formatTick(t, l.y_step);
    const cv::Size s = cv::getTextSize(label, kFont, kTickScale, 1, &base);
    cv::putText(img, label, cv::Point(p.x - 10 - s.width, static_cast<int>(std::lround(y)) + s.height / 2),
                kFont, kTickScale, kTextColor, 1, cv::LINE_AA);
  }
  if (!x_label_.empty()) {
    const double scale = fittingScale(x_label_, kAxisLabelScale, 1, p.width);
    putCentred(img, x_label_, {p.x + p.width / 2, p.y + p.height + 50}, scale, kTextColor, 1);
  }
  if (!y_label_.empty())
    putVertical(img, y_label_, {16, p.y + p.height / 2},
                fittingScale(y_label_, kAxisLabelScale, 1, p.height));
  if (!title_.empty()) {
    const double scale = fittingScale(title_, kTitleScale, 2, width_ - 20);
    int centre = p.x + p.width / 2;
    const int half = textWidth(title_, scale) / 2 + 10;
    centre = std::clamp(centre, half, std::max(half, width_ - half));
    putCentred(img, title_, {centre, p.y - 18}, scale, kTextColor, 2);
  }
}

void PlotCanvas::drawLegend(cv::Mat& img, const Layout& l) const {
  if (l.legend.empty()) return;
  std::vector<const Series*> entries;
  int widest = 0;
  for (const Series& s : series_) {
    if (s.label.empty() || s.kind == Series::Kind::Text) continue;
    entries.push_back(&s);
    widest = std::max(widest, textWidth(s.label, kLegendScale));
  }
  const int rows = (l.legend.height - 2 * kLegendPad) / kLegendRow;
  const int column_width = kLegendSample + kLegendGap + widest + kLegendColumnGap;
  cv::rectangle(img, l.legend, kWhite, cv::FILLED);
  cv::rectangle(img, l.legend, kLegendBorder, 1);
  for (size_t i = 0; i < entries.size(); ++i) {
    const Series& s = *entries[i];
    const int column = static_cast<int>(i) / rows, row = static_cast<int>(i) % rows;
    const int x = l.legend.x + kLegendPad + column * column_width;
    const int cy = l.legend.y + kLegendPad + row * kLegendRow + kLegendRow / 2;
    switch (s.kind) {
      case Series::Kind::Scatter:
        cv::circle(img, toFixed({x + kLegendSample / 2.0, static_cast<double>(cy)}),
                   static_cast<int>(std::min(s.size, 7) * kSubPixel), s.color, cv::FILLED, cv::LINE_AA,
                   kShift);
        break;
      case Series::Kind::Bars:
      case Series::Kind::Polygon: {
        const cv::Rect box(x + kLegendSample / 2 - 10, cy - 6, 20, 12);
        cv::rectangle(img, box, s.color, cv::FILLED);
        cv::rectangle(img, box, darker(s.color), 1);
        break;
      }
      default: {
        const std::vector<cv::Point2d> sample{{x + 1.0, static_cast<double>(cy)},
                                              {x + kLegendSample - 1.0, static_cast<double>(cy)}};
        drawRun(img, sample, s.color, std::min(s.size, 5), s.style);
        break;
      }
    }
    int base = 0;
    const cv::Size ts = cv::getTextSize(s.label, kFont, kLegendScale, 1, &base);
    cv::putText(img, s.label, cv::Point(x + kLegendSample + kLegendGap, cy + ts.height / 2), kFont,
                kLegendScale, kTextColor, 1, cv::LINE_AA);
  }
}

void writePng(const cv::Mat& img, const std::string& png_path) {
  std::string extension = std::filesystem::path(png_path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".png")
    throw std::runtime_error("cannot write plot '" + png_path + "': the name must end in .png");
  if (img.empty()) throw std::runtime_error("cannot write plot '" + png_path + "': empty image");
  const std::filesystem::path dir = std::filesystem::path(png_path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
    throw std::runtime_error("cannot write plot '" + png_path + "': directory '" + dir.string() +
                             "' does not exist");
  bool written = false;
  try {
    written = cv::imwrite(png_path, img, {cv::IMWRITE_PNG_COMPRESSION, 9});  // figures are kept in docs/
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot write plot '" + png_path + "': " + e.what());
  }
  if (!written) throw std::runtime_error("cannot write plot '" + png_path + "' (is the directory writable?)");
}

}  // namespace soccer_vision
