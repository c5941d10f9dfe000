#include "soccer_vision/calibration/color_calibration.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "soccer_vision/segmentation/illumination_adaptation.h"

namespace soccer_vision {

cv::Mat classifiedColors(const cv::Mat& image, PixelLayout layout) {
  checkImageFitsLayout(image, layout);
  cv::Mat bgr(image.size(), CV_8UC3);
  const cv::Size labels = labelSize(image.size(), layout);
  const int scale = isBayer(layout) ? 2 : 1;
  for (int y = 0; y < labels.height; ++y) {
    const LabelRow row = labelRow(image, layout, y);
    for (int x = 0; x < labels.width; ++x) {
      const int i = x * row.step;
      const cv::Vec3b c(row.b[i], static_cast<std::uint8_t>((row.g1[i] + row.g2[i] + 1) >> 1), row.r[i]);
      for (int dy = 0; dy < scale; ++dy) {
        for (int dx = 0; dx < scale; ++dx) bgr.at<cv::Vec3b>(y * scale + dy, x * scale + dx) = c;
      }
    }
  }
  return bgr;
}

ColorTable calibrateColorTable(const std::vector<CalibrationImage>& images, const ColorTableParams& params,
                               CalibrationLight light) {
  if (images.empty()) throw std::invalid_argument("colour calibration needs at least one image");
  std::vector<cv::Mat> bgr;
  for (const auto& image : images) {
    if (image.bgr.type() != CV_8UC3) throw std::invalid_argument("colour calibration needs bgr8 images");
    if (image.bgr.size() != images.front().bgr.size()) {
      throw std::invalid_argument("calibration images must all have the same size");
    }
    bgr.push_back(image.bgr);
  }
  const IlluminationAdaptation reference = IlluminationAdaptation::fromImages(bgr, PixelLayout::Bgr);
  const bool normalized = light == CalibrationLight::Normalized;

  ClassSamplePixels pixels;
  for (const auto& image : images) {
    // Each image's samples under that image's own light: with several images taken at
    // different times, each is normalised by what its blocks showed.
    const BlockOffsets adjustment =
        normalized ? reference.gainsFor(blockLightLevels(image.bgr, PixelLayout::Bgr,
                                                         expectedLightLevels(image.bgr, PixelLayout::Bgr)))
                   : BlockOffsets{};
    for (const auto& [cls, positions] : samplePixelPositions(image.bgr.size(), image.samples)) {
      auto& all = pixels[cls];
      for (const cv::Point& p : positions) {
        const cv::Vec3b c = image.bgr.at<cv::Vec3b>(p);
        const int v = std::max({c[0], c[1], c[2]});
        const int gain = normalized ? adjustment.gains.at<std::uint16_t>(p.y / BlockOffsets::kBlockSize,
                                                                         p.x / BlockOffsets::kBlockSize)
                                    : ColorTable::kUnitGain;
        all.push_back({c, static_cast<std::uint8_t>(ColorTable::adjustedV(v, 0, gain))});
      }
    }
  }
  // Polygons outside the image or smaller than a pixel leave a class with no pixel.
  for (auto it = pixels.begin(); it != pixels.end();)
    it = it->second.empty() ? pixels.erase(it) : std::next(it);
  if (pixels.empty()) throw std::invalid_argument("the sample polygons select no pixel");
  return ColorTable::buildFromSamplePixels(pixels, params)
      .withIlluminationReference(reference.reference())
      .withIlluminationLevels(normalized ? reference.referenceLevels() : cv::Mat());
}

}  // namespace soccer_vision
