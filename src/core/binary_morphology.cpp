#include "soccer_vision/binary_morphology.h"

#include <algorithm>
#include <cstring>

namespace soccer_vision {

void BitMask::reset(cv::Size size) {
  width_ = size.width;
  height_ = size.height;
  words_per_row_ = (size.width + 63) / 64;
  words_.assign(static_cast<std::size_t>(words_per_row_) * height_, 0);
}

std::uint64_t BitMask::validBits(int w) const {
  const int bits = std::min(64, width_ - 64 * w);
  return bits >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << bits) - 1;
}

namespace {

// One bit per byte of `bytes` that equals the byte broadcast in `pattern` (bit i for byte
// i, little-endian), eight pixels per step without branches or SIMD intrinsics.
std::uint64_t equalBytes(std::uint64_t bytes, std::uint64_t pattern) {
  constexpr std::uint64_t kLow7 = 0x7F7F7F7F7F7F7F7FULL;
  const std::uint64_t diff = bytes ^ pattern;
  const std::uint64_t zero_high = ~(((diff & kLow7) + kLow7) | diff | kLow7);  // 0x80 where diff byte is 0
  return ((zero_high >> 7) * 0x0102040810204080ULL) >> 56;
}

}  // namespace

void BitMask::setFromLabels(const cv::Mat& labels, std::uint8_t value) {
  CV_Assert(labels.type() == CV_8UC1);
  reset(labels.size());
  const std::uint64_t pattern = 0x0101010101010101ULL * value;
  const int whole = width_ / 8 * 8;
  for (int y = 0; y < height_; ++y) {
    const std::uint8_t* in = labels.ptr<std::uint8_t>(y);
    std::uint64_t* out = row(y);
    for (int x = 0; x < whole; x += 8) {
      std::uint64_t bytes;
      std::memcpy(&bytes, in + x, sizeof bytes);
      out[x >> 6] |= equalBytes(bytes, pattern) << (x & 63);
    }
    for (int x = whole; x < width_; ++x) out[x >> 6] |= std::uint64_t(in[x] == value) << (x & 63);
  }
}

cv::Mat BitMask::toMat() const {
  cv::Mat out(height_, width_, CV_8UC1);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) out.at<std::uint8_t>(y, x) = at(x, y) ? 255 : 0;
  }
  return out;
}

namespace {

// Both passes combine, for output pixel x, the input pixels x + d for d in
// [-anchor, k - 1 - anchor] (OpenCV's anchored window; its default anchor is k/2). Outside the mask the input is the
// identity of the combination (1 for AND = erosion, 0 for OR = dilation), which is
// OpenCV's default border, so out-of-range rows and bits can simply be left out.
template <bool kErode>
std::uint64_t combine(std::uint64_t a, std::uint64_t b) {
  return kErode ? a & b : a | b;
}

template <bool kErode>
void columnPass(const BitMask& in, int k, int anchor, BitMask& out) {
  const int first = -anchor, last = k - 1 - anchor;
  const int words = in.wordsPerRow();
  for (int y = 0; y < in.height(); ++y) {
    std::uint64_t* o = out.row(y);
    std::copy(in.row(y), in.row(y) + words, o);
    for (int d = std::max(first, -y); d <= std::min(last, in.height() - 1 - y); ++d) {
      if (d == 0) continue;
      const std::uint64_t* r = in.row(y + d);
      for (int w = 0; w < words; ++w) o[w] = combine<kErode>(o[w], r[w]);
    }
  }
}

// In place, row by row: a copy of the row with an identity word on each side makes the
// shifts across word boundaries branch-free; the bits beyond the width are set to the
// identity for the pass and cleared after it.
template <bool kErode>
void rowPass(BitMask& mask, int k, int anchor, std::vector<std::uint64_t>& padded) {
  const int first = -anchor, last = k - 1 - anchor;
  const int words = mask.wordsPerRow();
  const std::uint64_t identity = kErode ? ~std::uint64_t(0) : 0;
  const std::uint64_t tail = mask.validBits(words - 1);
  padded.resize(static_cast<std::size_t>(words) + 2);
  for (int y = 0; y < mask.height(); ++y) {
    std::uint64_t* row = mask.row(y);
    padded[0] = identity;
    std::copy(row, row + words, padded.begin() + 1);
    padded[static_cast<std::size_t>(words)] |= identity & ~tail;
    padded[static_cast<std::size_t>(words) + 1] = identity;
    for (int w = 0; w < words; ++w) {
      const std::uint64_t* p = padded.data() + w + 1;
      std::uint64_t acc = p[0];
      for (int d = first; d <= last; ++d) {
        if (d > 0) acc = combine<kErode>(acc, (p[0] >> d) | (p[1] << (64 - d)));
        if (d < 0) acc = combine<kErode>(acc, (p[0] << -d) | (p[-1] >> (64 + d)));
      }
      row[w] = acc;
    }
    row[words - 1] &= tail;
  }
}

template <bool kErode>
void squarePass(const BitMask& in, int k, int anchor, BitMask& out, MorphologyScratch& scratch) {
  if (anchor < 0) anchor = k / 2;
  CV_Assert(k >= 1 && k < 64 && anchor < k && &in != &out);
  out.reset(cv::Size(in.width(), in.height()));
  if (in.width() == 0 || in.height() == 0) return;
  columnPass<kErode>(in, k, anchor, out);
  rowPass<kErode>(out, k, anchor, scratch.padded_row);
}

}  // namespace

void erode(const BitMask& in, int k, BitMask& out, MorphologyScratch& scratch, int anchor) {
  squarePass<true>(in, k, anchor, out, scratch);
}

void dilate(const BitMask& in, int k, BitMask& out, MorphologyScratch& scratch, int anchor) {
  squarePass<false>(in, k, anchor, out, scratch);
}

void openThenClose(BitMask& mask, int k, MorphologyScratch& scratch) {
  const int a = k / 2, reflected = k - 1 - k / 2;  // equal for odd k
  erode(mask, k, scratch.temp, scratch, a);
  dilate(scratch.temp, k, mask, scratch, reflected);
  dilate(mask, k, scratch.temp, scratch, a);
  erode(scratch.temp, k, mask, scratch, reflected);
}

}  // namespace soccer_vision
