#include "soccer_vision/segmentation/ball_streak_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace soccer_vision {
namespace {

using Rgb = cv::Vec3d;

// The mean colour of a class's valid samples (its naive-Bayes means) in RGB.
Rgb meanColor(const ClassStatistics& s) {
  const auto bgr = hsvToBgr({s.mean_h_valid, s.mean_s, s.mean_v});
  return {static_cast<double>(bgr[2]), static_cast<double>(bgr[1]), static_cast<double>(bgr[0])};
}

Rgb toLinear(const Rgb& c, double gamma) {
  Rgb out;
  for (int i = 0; i < 3; ++i) out[i] = 255.0 * std::pow(c[i] / 255.0, gamma);
  return out;
}

Rgb toEncoded(const Rgb& c, double gamma) {
  Rgb out;
  for (int i = 0; i < 3; ++i) out[i] = 255.0 * std::pow(std::max(0.0, c[i]) / 255.0, 1.0 / gamma);
  return out;
}

double distanceToSegment(const Rgb& p, const Rgb& a, const Rgb& b) {
  const Rgb ab = b - a;
  const double length2 = ab.dot(ab);
  const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return cv::norm(p - (a + t * ab));
}

// The mixtures from `min_share` of the ball to the ball itself, as a polyline (a straight
// line in the encoded values, a curve through them when mixed in linear light).
std::vector<Rgb> mixtureLine(const Rgb& ball, const Rgb& carpet, double min_share, double gamma,
                             bool linear) {
  constexpr int kSteps = 16;
  const Rgb ball_l = toLinear(ball, gamma), carpet_l = toLinear(carpet, gamma);
  std::vector<Rgb> line;
  for (int i = 0; i <= kSteps; ++i) {
    const double a = min_share + (1.0 - min_share) * i / kSteps;
    line.push_back(linear ? toEncoded(a * ball_l + (1 - a) * carpet_l, gamma) : a * ball + (1 - a) * carpet);
  }
  return line;
}

double distanceToLine(const Rgb& p, const std::vector<Rgb>& line) {
  double best = HUGE_VAL;
  for (std::size_t i = 1; i < line.size(); ++i)
    best = std::min(best, distanceToSegment(p, line[i - 1], line[i]));
  return best;
}

}  // namespace

void BallStreakParams::validate() const {
  if (!(min_ball_share > 0 && min_ball_share < 1))
    throw std::invalid_argument("ball streak: min_ball_share must lie in (0, 1)");
  if (!(tolerance > 0 && tolerance < 1))
    throw std::invalid_argument("ball streak: tolerance must lie in (0, 1)");
  if (!(gamma >= 1 && gamma <= 4)) throw std::invalid_argument("ball streak: gamma must lie in [1, 4]");
}

std::optional<ColorTable> ballStreakTable(const ColorTable& table, const BallStreakParams& params) {
  params.validate();
  const ClassStatistics& ball = table.statistics().classes[static_cast<int>(ColorClass::Orange)];
  const ClassStatistics& carpet = table.statistics().classes[static_cast<int>(ColorClass::Carpet)];
  if (ball.valid == 0 || carpet.valid == 0) return std::nullopt;
  const Rgb ball_rgb = meanColor(ball), carpet_rgb = meanColor(carpet);
  const double reach = params.tolerance * cv::norm(ball_rgb - carpet_rgb);
  const std::vector<Rgb> lines[] = {
      mixtureLine(ball_rgb, carpet_rgb, params.min_ball_share, params.gamma, false),
      mixtureLine(ball_rgb, carpet_rgb, params.min_ball_share, params.gamma, true)};

  const ColorTableParams& q = table.params();
  std::vector<std::pair<std::size_t, ColorClass>> cells;
  cells.reserve(table.cells().size());
  for (int h = 0; h < q.h_bins; ++h) {
    for (int s = 0; s < q.s_bins; ++s) {
      for (int v = 0; v < q.v_bins; ++v) {
        const std::size_t index = table.cellIndex(h, s, v);
        const ColorClass held = table.cells()[index];
        bool streak = held == ColorClass::Orange;
        // The carpet keeps its cells (its texture must not turn orange). A robot marker
        // colour does not: its Gaussian reaches the streak's colours (yellow takes a 60 %
        // mixture), and a marker that reads as the streak in a ball window is a cluster on
        // a robot's top, which ball detection refuses. Claimed: a probe of the cell (as
        // generalisation probes it) near either mixture line.
        for (int k = 0; k < kCellProbes && !streak && held != ColorClass::Carpet; ++k) {
          const auto bgr = hsvToBgr(cellProbe(q, h, s, v, k));
          const Rgb p(bgr[2], bgr[1], bgr[0]);
          streak = distanceToLine(p, lines[0]) <= reach || distanceToLine(p, lines[1]) <= reach;
        }
        cells.emplace_back(index, streak ? ColorClass::Orange : ColorClass::None);
      }
    }
  }
  return table.withCells(cells);
}

}  // namespace soccer_vision
