// The paper's adaptive illumination (§III-B): the image is split into 32x32 blocks; the
// reference mean V of each block comes from the calibration images; at run time
// Δv = v_ref - v_now per block and v' = v + k·Δv before the table lookup (k = 0.3).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/pixel_classifier.h"

namespace soccer_vision {

// Mean V (max channel, 8-bit units) per 32x32 block of an image in any supported layout
// (Bayer: of its quads), CV_32FC1 of ceil(h/32) x ceil(w/32). `sample_step` > 1 reads every
// n-th row and column of each block only (an estimate, documented as such, to keep the
// run-time pass well under a full read of the frame): the label pixels whose offsets from
// the block's first label pixel are multiples of n in x and y. Blocks cut by the image
// border average the pixels they have. Throws std::invalid_argument for an image that does
// not fit the layout or sample_step < 1.
cv::Mat blockMeanV(const cv::Mat& image, PixelLayout layout, int sample_step = 1);

class IlluminationAdaptation {
 public:
  // Reference from one or more calibration images of the same size (mean of their block
  // means). Throws std::invalid_argument for no images or different sizes.
  static IlluminationAdaptation fromImages(const std::vector<cv::Mat>& images, PixelLayout layout);
  IlluminationAdaptation() = default;  // no reference: offsets are zero
  explicit IlluminationAdaptation(cv::Mat reference_means) : reference_(std::move(reference_means)) {}

  const cv::Mat& reference() const { return reference_; }
  bool hasReference() const { return !reference_.empty(); }

  // Offsets round(k * (v_ref - v_now)) per block for this frame (std::lround: half away
  // from zero), clamped to ±max_offset (0..255, else std::invalid_argument). Zero offsets
  // (an empty BlockOffsets) when k == 0, without a reference, or for a frame of another
  // block grid size (reported through `size_mismatch`).
  BlockOffsets offsets(const cv::Mat& image, PixelLayout layout, double k, int sample_step,
                       int max_offset = 64, bool* size_mismatch = nullptr) const;

 private:
  cv::Mat reference_;
};

}  // namespace soccer_vision
