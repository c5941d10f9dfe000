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

void BitMask::resize(cv::Size size) {
  width_ = size.width;
  height_ = size.height;
  words_per_row_ = (size.width + 63) / 64;
  words_.resize(static_cast<std::size_t>(words_per_row_) * height_);
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

// Bit x of the result is bit x + d of the row (d > 0) or x - |d| (d < 0): `p` points at
// the word, with its neighbours at p[-1] and p[1].
template <int D>
std::uint64_t shifted(const std::uint64_t* p) {
  if constexpr (D > 0) return (p[0] >> D) | (p[1] << (64 - D));
  if constexpr (D < 0) return (p[0] << -D) | (p[-1] >> (64 + D));
  return p[0];
}

// The horizontal combination of one padded row word, window [First, Last] known at
// compile time (the kernels of the region extractor: 2 and 3).
template <bool kErode, int First, int Last>
std::uint64_t rowWindow(const std::uint64_t* p) {
  std::uint64_t acc = p[0];
  if constexpr (First <= -2) acc = combine<kErode>(acc, shifted<-2>(p));
  if constexpr (First <= -1) acc = combine<kErode>(acc, shifted<-1>(p));
  if constexpr (Last >= 1) acc = combine<kErode>(acc, shifted<1>(p));
  if constexpr (Last >= 2) acc = combine<kErode>(acc, shifted<2>(p));
  return acc;
}

template <bool kErode>
std::uint64_t rowWindow(const std::uint64_t* p, int first, int last) {
  std::uint64_t acc = p[0];
  for (int d = first; d <= last; ++d) {
    if (d > 0) acc = combine<kErode>(acc, (p[0] >> d) | (p[1] << (64 - d)));
    if (d < 0) acc = combine<kErode>(acc, (p[0] << -d) | (p[-1] >> (64 + d)));
  }
  return acc;
}

// One pass, row by row: the column combination of the rows y + d into a padded row (an
// identity word on each side makes the shifts across word boundaries branch-free; the
// bits beyond the width are the identity during the pass), then the row combination
// into the output. Every output word is written.
template <bool kErode, int First, int Last>
void squareRows(const BitMask& in, int first, int last, BitMask& out, std::vector<std::uint64_t>& padded) {
  const int words = in.wordsPerRow(), height = in.height();
  const std::uint64_t identity = kErode ? ~std::uint64_t(0) : 0;
  const std::uint64_t tail = in.validBits(words - 1);
  padded.resize(static_cast<std::size_t>(words) + 2);
  std::uint64_t* column = padded.data() + 1;
  column[-1] = identity;
  column[words] = identity;
  for (int y = 0; y < height; ++y) {
    std::copy(in.row(y), in.row(y) + words, column);
    for (int d = std::max(first, -y); d <= std::min(last, height - 1 - y); ++d) {
      if (d == 0) continue;
      const std::uint64_t* r = in.row(y + d);
      for (int w = 0; w < words; ++w) column[w] = combine<kErode>(column[w], r[w]);
    }
    column[words - 1] |= identity & ~tail;
    std::uint64_t* o = out.row(y);
    for (int w = 0; w < words; ++w) {
      if constexpr (First <= Last) {
        o[w] = rowWindow<kErode, First, Last>(column + w);
      } else {
        o[w] = rowWindow<kErode>(column + w, first, last);
      }
    }
    o[words - 1] &= tail;
  }
}

template <bool kErode>
void squarePass(const BitMask& in, int k, int anchor, BitMask& out, MorphologyScratch& scratch) {
  if (anchor < 0) anchor = k / 2;
  CV_Assert(k >= 1 && k < 64 && anchor < k && &in != &out);
  out.resize(cv::Size(in.width(), in.height()));
  if (in.width() == 0 || in.height() == 0) return;
  const int first = -anchor, last = k - 1 - anchor;
  auto& padded = scratch.padded_row;
  if (first == -1 && last == 1) return squareRows<kErode, -1, 1>(in, first, last, out, padded);
  if (first == -1 && last == 0) return squareRows<kErode, -1, 0>(in, first, last, out, padded);
  if (first == 0 && last == 1) return squareRows<kErode, 0, 1>(in, first, last, out, padded);
  if (first == -2 && last == 2) return squareRows<kErode, -2, 2>(in, first, last, out, padded);
  squareRows<kErode, 1, 0>(in, first, last, out, padded);  // any other window, at run time
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
