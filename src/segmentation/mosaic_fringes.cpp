#include "soccer_vision/segmentation/mosaic_fringes.h"

namespace soccer_vision {

std::uint32_t quadsWithAgreeingGreens(const FrameClassifier& frame, const PixelRun* begin,
                                      const PixelRun* end, cv::Point origin) {
  std::uint32_t agreeing = 0;
  for (const PixelRun* run = begin; run != end; ++run) {
    const LabelRow row = frame.row(origin.y + run->y);
    for (int x = origin.x + run->x_begin; x < origin.x + run->x_end; ++x) {
      const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(x) * row.step;
      agreeing += greensAgree(row.g1[at], row.g2[at]);
    }
  }
  return agreeing;
}

}  // namespace soccer_vision
