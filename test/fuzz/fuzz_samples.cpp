// Colour samples YAML -> sample pixels of a small image (the path of calibrate_colors,
// evaluate --samples and ~calibrate).
#include <opencv2/core.hpp>

#include "fuzz_target.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/segmentation/color_table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto samples = soccer_vision::parseColorSamples(soccer_vision_fuzz::asText(data, size), "fuzz");
    soccer_vision::samplePixelPositions(cv::Size(64, 48), samples);
  } catch (const std::exception&) {
  }
  return 0;
}
