#include "soccer_vision/color_calibration.h"

#include <iterator>
#include <stdexcept>

#include "soccer_vision/illumination_adaptation.h"

namespace soccer_vision {

ColorTable calibrateColorTable(const std::vector<CalibrationImage>& images, const ColorTableParams& params) {
  if (images.empty()) throw std::invalid_argument("colour calibration needs at least one image");
  ClassPixels pixels;
  std::vector<cv::Mat> bgr;
  for (const auto& image : images) {
    if (image.bgr.type() != CV_8UC3) throw std::invalid_argument("colour calibration needs bgr8 images");
    if (image.bgr.size() != images.front().bgr.size()) {
      throw std::invalid_argument("calibration images must all have the same size");
    }
    for (auto& [cls, px] : collectSamplePixels(image.bgr, image.samples)) {
      auto& all = pixels[cls];
      all.insert(all.end(), px.begin(), px.end());
    }
    bgr.push_back(image.bgr);
  }
  // Polygons outside the image or smaller than a pixel leave a class with no pixel.
  for (auto it = pixels.begin(); it != pixels.end();) it = it->second.empty() ? pixels.erase(it) : std::next(it);
  if (pixels.empty()) throw std::invalid_argument("the sample polygons select no pixel");
  return ColorTable::build(pixels, params)
      .withIlluminationReference(IlluminationAdaptation::fromImages(bgr, PixelLayout::Bgr).reference());
}

}  // namespace soccer_vision
