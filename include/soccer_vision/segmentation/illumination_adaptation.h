// Block-wise illumination adaptation, in two modes chosen by the colour table:
//
//  * the paper's (§III-B), for tables of V as captured: the image is split into 32x32
//    blocks; the reference mean V of each block comes from the calibration images; at run
//    time Δv = v_ref - v_now per block and v' = v + k·Δv before the table lookup (k = 0.3);
//  * normalised V, for tables with illumination levels (the default calibration): the light
//    level L(b) of each block is measured on the carpet, and every V is scaled by
//    L_mean / L(b), at calibration with the calibration image's levels and at run time
//    with the current frame's. A marker then shows the same V wherever it moves and
//    whatever the global light does, which the paper's mode cannot give: its reference only
//    follows a change in time at a fixed place (not a robot moving into darker light), its
//    additive offset follows the carpet's V and so under-corrects bright markers under a
//    multiplicative change, and its plain block mean drops when a black robot enters the
//    block.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/segmentation/pixel_classifier.h"

namespace soccer_vision {

// Mean V (max channel, 8-bit units) per 32x32 block of an image in any supported layout
// (Bayer: of its quads), CV_32FC1 of ceil(h/32) x ceil(w/32). `sample_step` > 1 reads every
// n-th row and column of each block only (an estimate, documented as such, to keep the
// run-time pass well under a full read of the frame): the label pixels whose offsets from
// the block's first label pixel are multiples of n in x and y. Blocks cut by the image
// border average the pixels they have. Throws std::invalid_argument for an image that does
// not fit the layout or sample_step < 1.
// `selected` (optional, CV_8UC1 of the block grid): only blocks with a non-zero entry are
// read, the others are 0 (search windows: the cost follows the windows, not the frame).
cv::Mat blockMeanV(const cv::Mat& image, PixelLayout layout, int sample_step = 1,
                   const cv::Mat1b& selected = cv::Mat1b());
// The blocks (of the image's block grid) that rectangles in image pixels overlap.
cv::Mat1b blocksMeeting(const cv::Mat& image, PixelLayout layout, const std::vector<cv::Rect>& rects);

// Light level per block. A block's reading: the mean V of the read pixels (as blockMeanV
// reads them) whose V lies within [kLevelBandLow, kLevelBandHigh] x expected(b), i.e. the
// carpet, leaving out robot tops (far darker), lines and most markers (far brighter); none
// where fewer than kMinLevelFraction of the read pixels fall in the band (covered by
// robots), clean where at least kCleanLevelFraction do. A clean reading is the block's
// level. Where a robot half covers a block, the anti-aliased edges of its top and markers
// are a good part of the pixels in the band (in a crowd: enough to push markers out of
// their colour cells), so any other block gets expected(b) x the median of reading /
// expected over the clean readings within kLevelNeighbourhood blocks, else over all
// readings there, else over all blocks (x 1 when no block has a reading): the light is
// smooth over a few blocks. `expected`: CV_32FC1 of the image's block grid, positive.
// `selected` as for blockMeanV: blocks left out get the median over all read blocks.
// Throws std::invalid_argument like blockMeanV, or for `expected` of another size or type.
constexpr double kLevelBandLow = 0.7, kLevelBandHigh = 1.4, kMinLevelFraction = 0.25,
                 kCleanLevelFraction = 0.75;
constexpr int kLevelNeighbourhood = 1;
cv::Mat blockLightLevels(const cv::Mat& image, PixelLayout layout, const cv::Mat& expected,
                         int sample_step = 1, const cv::Mat1b& selected = cv::Mat1b());
// Expected levels for an image without prior knowledge (calibration): per block the
// median over its 5x5 neighbourhood of the blocks' median V, which robots (about one
// block in size) and lines cannot take over.
cv::Mat expectedLightLevels(const cv::Mat& image, PixelLayout layout);

class IlluminationAdaptation {
 public:
  // Reference from one or more calibration images of the same size: the mean of their
  // block means, and the mean of their light levels (blockLightLevels with
  // expectedLightLevels). Throws std::invalid_argument for no images or different sizes.
  static IlluminationAdaptation fromImages(const std::vector<cv::Mat>& images, PixelLayout layout);
  IlluminationAdaptation() = default;  // no reference: offsets are zero
  // Means for the paper's mode; levels (optional) select the normalised mode.
  explicit IlluminationAdaptation(cv::Mat reference_means, cv::Mat reference_levels = {})
      : reference_(std::move(reference_means)),
        levels_(std::move(reference_levels)),
        mean_level_(levels_.empty() ? 0.0 : cv::mean(levels_)[0]) {}

  const cv::Mat& reference() const { return reference_; }
  bool hasReference() const { return !reference_.empty(); }
  const cv::Mat& referenceLevels() const { return levels_; }
  bool normalizes() const { return !levels_.empty(); }
  // The centre of the band in which each block's carpet is read (normalised mode), in the
  // reference levels' units: the reference levels unless learned (OnlineCalibration).
  const cv::Mat& expectedLevels() const { return expected_.empty() ? levels_ : expected_; }
  // This adaptation with those expected levels (copied; empty: the reference levels). The
  // gains still bring V to the reference's mean level. Throws std::invalid_argument unless
  // `expected` is empty or a CV_32FC1 of finite positive values of the reference levels' size.
  IlluminationAdaptation withExpectedLevels(const cv::Mat& expected) const;

  // Gains round(256 * L_mean / level(b)) per block (L_mean: mean of the reference levels),
  // clamped to [kUnitGain / 8, 8 * kUnitGain]: they bring V under these levels to V under
  // the reference's mean level. Empty when not normalizing. Throws std::invalid_argument
  // for levels of another size or type than the reference levels.
  BlockOffsets gainsFor(const cv::Mat& levels) const;

  // The adjustment of this frame's blocks.
  // Normalised mode: gainsFor(the frame's levels), measured by blockLightLevels every
  //   sample_step-th row and column around the reference levels times the global change
  //   (the median ratio of the blocks' mean V to the reference means, read at twice the
  //   step); k == 0: gainsFor(reference levels), the light as calibrated (no adaptation).
  // Paper's mode: offsets round(k * (v_ref - v_now)) per block (std::lround: half away
  //   from zero), clamped to ±max_offset; zero offsets (an empty BlockOffsets) when k == 0
  //   or without a reference.
  // Both: an empty BlockOffsets for a frame of another block grid size (reported through
  // `size_mismatch`); max_offset must be in 0..255, else std::invalid_argument.
  // `windows` (image pixels, optional): only the blocks they meet are measured (global
  // change and levels from those blocks alone); the other blocks get the fill level of
  // covered blocks (normalised) or no offset (paper's), which only matters where a region
  // grows out of the windows.
  BlockOffsets offsets(const cv::Mat& image, PixelLayout layout, double k, int sample_step,
                       int max_offset = 64, bool* size_mismatch = nullptr,
                       const std::vector<cv::Rect>* windows = nullptr) const;

 private:
  BlockOffsets paperOffsets(const cv::Mat& image, PixelLayout layout, double k, int sample_step,
                            int max_offset, const cv::Mat1b& selected) const;
  cv::Mat currentLevels(const cv::Mat& image, PixelLayout layout, int sample_step,
                        const cv::Mat1b& selected) const;

  cv::Mat reference_;
  cv::Mat levels_;
  cv::Mat expected_;       // learned band centres; empty: levels_
  double mean_level_ = 0;  // of levels_: L_mean of gainsFor, once per reference
};

}  // namespace soccer_vision
