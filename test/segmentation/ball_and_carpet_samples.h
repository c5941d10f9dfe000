// Test helper: sample pixels of the ball, of the two marker colours next to its hue (yellow,
// red) and of the carpet, each with a little spread: the tests of the ball's mixtures with
// the carpet (test_color_table.cpp, test_ball_streak_table.cpp).
#pragma once

#include "soccer_vision/segmentation/color_table.h"

namespace soccer_vision::test {

inline const cv::Vec3d kSampledBall(8, 95, 215), kSampledCarpet(55, 120, 50);  // BGR

inline ClassSamplePixels ballAndCarpetSamples() {
  ClassSamplePixels samples;
  for (int i = 0; i < 9; ++i) {
    const int d = i % 3 - 1;
    samples[ColorClass::Orange].push_back({cv::Vec3b(8 + d, 95 - d, 215), 215});
    samples[ColorClass::Yellow].push_back({cv::Vec3b(32 + d, 170 - d, 240), 240});
    samples[ColorClass::Red].push_back({cv::Vec3b(38 + d, 40 - d, 230 + d), 230});
  }
  for (int i = 0; i < 40; ++i) {
    const int d = i % 5 - 2;
    samples[ColorClass::Carpet].push_back({cv::Vec3b(55 + d, 120 - d, 50 + d), 120});
  }
  return samples;
}

}  // namespace soccer_vision::test
