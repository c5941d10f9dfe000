#include "soccer_vision/segmentation/floor_surround.h"

#include <algorithm>
#include <cmath>

#include "soccer_vision/segmentation/region_moments.h"

namespace soccer_vision {

std::optional<double> floorShareAround(const FrameClassifier& colors, const Region& region) {
  const MomentEllipse outline = momentEllipse(region, 0.0);
  if (!std::isfinite(outline.sd.major) || !std::isfinite(outline.cx) || !std::isfinite(outline.cy))
    return std::nullopt;
  const double margin = std::max(2.0, outline.sd.minor);
  const double a = outline.a + margin, b = outline.b + margin;
  const double ca = std::cos(outline.angle), sa = std::sin(outline.angle);
  const cv::Size size = colors.labelSize();
  const ClassMask floor = classBit(ColorClass::Carpet) | classBit(ColorClass::Line);
  int inside = 0, on_floor = 0;
  for (int k = 0; k < kFloorRingPoints; ++k) {
    const double t = 2 * M_PI * k / kFloorRingPoints;
    const double u = a * std::cos(t), v = b * std::sin(t);
    const int x = static_cast<int>(std::lround(outline.cx + ca * u - sa * v));
    const int y = static_cast<int>(std::lround(outline.cy + sa * u + ca * v));
    if (x < 0 || y < 0 || x >= size.width || y >= size.height) continue;
    ++inside;
    on_floor += colors.classifyPixel(x, y, floor) != static_cast<std::uint8_t>(ColorClass::None);
  }
  if (inside == 0) return std::nullopt;
  return static_cast<double>(on_floor) / inside;
}

}  // namespace soccer_vision
