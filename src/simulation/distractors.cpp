#include "soccer_vision/simulation/distractors.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "soccer_vision/common/class_colors.h"

namespace soccer_vision {

namespace {

constexpr double kClearance = 0.02;  // m beyond the lines' outer edges
constexpr double kReach = 0.5;       // m beyond the carpet's edge

// The colours people wear near a field: team and ball colours most of all.
cv::Vec3f drawColour(cv::RNG& rng) {
  static const ColorClass kClasses[] = {ColorClass::Blue, ColorClass::Yellow, ColorClass::Orange,
                                        ColorClass::Blue, ColorClass::Yellow, ColorClass::Orange,
                                        ColorClass::Pink, ColorClass::Green,  ColorClass::Red};
  const int pick = rng.uniform(0, static_cast<int>(std::size(kClasses)) + 2);
  cv::Vec3f c = pick < static_cast<int>(std::size(kClasses))
                    ? classAlbedo(kClasses[pick])
                    : (pick == static_cast<int>(std::size(kClasses)) ? albedoFromRgb(25, 25, 30)
                                                                     : albedoFromRgb(200, 200, 195));
  for (int ch = 0; ch < 3; ++ch) c[ch] *= static_cast<float>(rng.uniform(0.85, 1.15));
  return c;
}

}  // namespace

float Distractor::sdf(float px, float py) const {
  const float c = static_cast<float>(std::cos(angle)), s = static_cast<float>(std::sin(angle));
  const float dx = px - static_cast<float>(x), dy = py - static_cast<float>(y);
  const float u = c * dx + s * dy, v = -s * dx + c * dy;
  const float a = static_cast<float>(half_length), b = static_cast<float>(half_width);
  if (kind == Kind::Cable) {
    const float along = std::max(std::abs(u) - a, 0.f);
    return std::hypot(along, v) - b;
  }
  // Scaled-circle approximation, exact on the axes: distance in units of the minor axis.
  const float k = std::hypot(u / a, v / b);
  return (k - 1) * std::min(a, b);
}

double distanceOutsideLines(const FieldGeometry& field, double x, double y) {
  const double hx = field.halfLength() + field.line_width / 2, hy = field.halfWidth() + field.line_width / 2;
  const double qx = std::abs(x) - hx, qy = std::abs(y) - hy;
  return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
}

std::vector<Distractor> distractorLayout(int count, const FieldGeometry& field, std::uint64_t seed) {
  std::vector<Distractor> out;
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ULL + 0x5851F42D4C957F2DULL);
  const double hx = field.carpetHalfLength() + kReach;
  const double hy = field.carpetHalfWidth() + kReach;
  const auto fits = [&](const Distractor& d) {
    return distanceOutsideLines(field, d.x, d.y) >= d.boundingRadius() + kClearance && std::abs(d.x) <= hx &&
           std::abs(d.y) <= hy;
  };
  for (int made = 0, tries = 0; made < count && tries < 1000 * (count + 1); ++tries) {
    const double x = rng.uniform(-hx, hx), y = rng.uniform(-hy, hy);
    // Facing the field centre (people look at the game).
    const double facing = std::atan2(-y, -x) + rng.uniform(-0.5, 0.5);
    std::vector<Distractor> parts;
    const int kind = rng.uniform(0, 4);  // 0, 1: person; 2: clothes; 3: cable
    if (kind <= 1) {
      const cv::Vec3f shoes = drawColour(rng), legs = drawColour(rng);
      const double cf = std::cos(facing), sf = std::sin(facing);
      for (double side : {-0.11, 0.11}) {
        const double sx = x - sf * side, sy = y + cf * side;
        parts.push_back(
            {Distractor::Kind::Ellipse, sx + 0.05 * cf, sy + 0.05 * sf, 0.14, 0.05, facing, shoes});
        parts.push_back(
            {Distractor::Kind::Ellipse, sx - 0.03 * cf, sy - 0.03 * sf, 0.07, 0.065, facing, legs});
      }
    } else if (kind == 2) {
      parts.push_back({Distractor::Kind::Ellipse, x, y, rng.uniform(0.2, 0.35), rng.uniform(0.12, 0.2),
                       rng.uniform(-M_PI, M_PI), drawColour(rng)});
    } else {
      parts.push_back({Distractor::Kind::Cable, x, y, rng.uniform(0.3, 1.0), 0.005, rng.uniform(-M_PI, M_PI),
                       drawColour(rng)});
    }
    if (!std::all_of(parts.begin(), parts.end(), fits)) continue;
    out.insert(out.end(), parts.begin(), parts.end());
    ++made;
  }
  return out;
}

}  // namespace soccer_vision
