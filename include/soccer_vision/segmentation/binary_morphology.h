// Binary morphology on bit-packed masks for the small areas of the region extractor:
// 64 pixels per machine word, so an erosion or dilation by a k x k square is a few shifts
// and ANDs/ORs per word instead of a call into OpenCV whose fixed cost dominates on
// areas of a few thousand pixels.
//
// Semantics are exactly cv::erode / cv::dilate with a k x k MORPH_RECT kernel, the given
// anchor (default (k/2, k/2)) and the default border: pixels outside the mask count as
// foreground for erosion and as background for dilation (so the image border neither eats
// nor grows regions). openThenClose is the *centred* opening and closing: the second pass
// of each uses the reflected anchor (k - 1 - k/2), so for even k the regions stay where
// they are — cv::morphologyEx uses one anchor for both passes and moves every region by a
// pixel right and down per operation. For odd k both are the same.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace soccer_vision {

// A binary image, row by row; in a row, pixel x is bit x % 64 of word x / 64. Bits
// beyond the width are always 0.
class BitMask {
 public:
  // All background.
  void reset(cv::Size size);
  // This size, contents unspecified (left from before, or background): for outputs
  // whose every word is written next, without the cost of clearing them first.
  void resize(cv::Size size);
  // Foreground where `labels` (CV_8UC1) equals `value`.
  void setFromLabels(const cv::Mat& labels, std::uint8_t value);
  cv::Mat toMat() const;  // CV_8UC1, 255 = foreground (tests, debugging)

  int width() const { return width_; }
  int height() const { return height_; }
  int wordsPerRow() const { return words_per_row_; }
  std::uint64_t* row(int y) { return words_.data() + static_cast<std::size_t>(y) * words_per_row_; }
  const std::uint64_t* row(int y) const {
    return words_.data() + static_cast<std::size_t>(y) * words_per_row_;
  }
  bool at(int x, int y) const { return (row(y)[x >> 6] >> (x & 63)) & 1; }
  // Mask of the valid bits of word `w` of a row.
  std::uint64_t validBits(int w) const;

 private:
  int width_ = 0, height_ = 0, words_per_row_ = 0;
  std::vector<std::uint64_t> words_;
};

// Reusable row buffer of the passes below.
struct MorphologyScratch {
  std::vector<std::uint64_t> padded_row;
  BitMask temp;
};

// k x k square (k >= 1), anchor in 0..k-1 (-1: k/2), `out` may not be `in`.
void erode(const BitMask& in, int k, BitMask& out, MorphologyScratch& scratch, int anchor = -1);
void dilate(const BitMask& in, int k, BitMask& out, MorphologyScratch& scratch, int anchor = -1);
// Centred opening then closing, in place: erode (k/2), dilate (k-1-k/2), dilate (k/2),
// erode (k-1-k/2).
void openThenClose(BitMask& mask, int k, MorphologyScratch& scratch);

}  // namespace soccer_vision
