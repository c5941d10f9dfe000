#include "soccer_vision/segmentation/binary_morphology.h"

#include <algorithm>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>  // SSE2: part of every x86-64 CPU
#endif

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
    int x = 0;
#if defined(__SSE2__)
    // 16 pixels per compare; x stays a multiple of 16, so the 16 bits never straddle words.
    const __m128i wanted = _mm_set1_epi8(static_cast<char>(value));
    for (; x + 16 <= width_; x += 16) {
      const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + x));
      const auto bits = static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(bytes, wanted)));
      out[x >> 6] |= std::uint64_t(bits) << (x & 63);
    }
#endif
    for (; x < whole; x += 8) {
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
// [-anchor, k - 1 - anchor] (OpenCV's anchored window; its default anchor is k/2). Outside the mask the input
// is the identity of the combination (1 for AND = erosion, 0 for OR = dilation), which is OpenCV's default
// border, so out-of-range rows and bits can simply be left out.
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

// A row window [First, Last] as a type (First > Last: known at run time only).
template <int First, int Last>
struct Window {
  static constexpr int first = First, last = Last;
};

// One pass, row by row: the column combination of the rows y + d into a padded row (an
// identity word on each side makes the shifts across word boundaries branch-free; the
// bits beyond the width are the identity during the pass), then the row combination
// into the output. Every output word is written.
template <bool kErode, int First, int Last>
void squareRows(const BitMask& in, int first, int last, int row_begin, int row_end, BitMask& out,
                std::vector<std::uint64_t>& padded) {
  const int words = in.wordsPerRow(), height = in.height();
  for (int y = 0; y < row_begin; ++y) std::fill(out.row(y), out.row(y) + words, 0);
  for (int y = row_end; y < height; ++y) std::fill(out.row(y), out.row(y) + words, 0);
  const std::uint64_t identity = kErode ? ~std::uint64_t(0) : 0;
  const std::uint64_t tail = in.validBits(words - 1);
  if (words == 1) {
    // Areas up to 64 px wide (most of the region extractor's): the row in a register,
    // between its identity words.
    for (int y = row_begin; y < row_end; ++y) {
      std::uint64_t window[3] = {identity, in.row(y)[0], identity};
      for (int d = std::max(first, -y); d <= std::min(last, height - 1 - y); ++d) {
        if (d != 0) window[1] = combine<kErode>(window[1], in.row(y + d)[0]);
      }
      window[1] |= identity & ~tail;
      if constexpr (First <= Last) {
        out.row(y)[0] = rowWindow<kErode, First, Last>(window + 1) & tail;
      } else {
        out.row(y)[0] = rowWindow<kErode>(window + 1, first, last) & tail;
      }
    }
    return;
  }
  padded.resize(static_cast<std::size_t>(words) + 2);
  std::uint64_t* column = padded.data() + 1;
  column[-1] = identity;
  column[words] = identity;
  for (int y = row_begin; y < row_end; ++y) {
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

// Rows outside [row_begin, row_end) are left out and written as background: the caller
// knows that they are background in the input and in the result.
template <bool kErode>
void squarePass(const BitMask& in, int k, int anchor, BitMask& out, MorphologyScratch& scratch,
                int row_begin = 0, int row_end = -1) {
  if (anchor < 0) anchor = k / 2;
  CV_Assert(k >= 1 && k < 64 && anchor < k && &in != &out);
  out.resize(cv::Size(in.width(), in.height()));
  if (in.width() == 0 || in.height() == 0) return;
  if (row_end < 0) row_end = in.height();
  const int first = -anchor, last = k - 1 - anchor;
  auto& padded = scratch.padded_row;
  auto rows = [&](auto window) {
    squareRows<kErode, decltype(window)::first, decltype(window)::last>(in, first, last, row_begin, row_end,
                                                                        out, padded);
  };
  if (first == -1 && last == 1) return rows(Window<-1, 1>());
  if (first == -1 && last == 0) return rows(Window<-1, 0>());
  if (first == 0 && last == 1) return rows(Window<0, 1>());
  if (first == -2 && last == 2) return rows(Window<-2, 2>());
  rows(Window<1, 0>());  // any other window, at run time
}

// First and one past the last row holding foreground (0, 0 when there is none).
std::pair<int, int> occupiedRows(const BitMask& mask) {
  auto occupied = [&](int y) {
    const std::uint64_t* row = mask.row(y);
    return std::any_of(row, row + mask.wordsPerRow(), [](std::uint64_t w) { return w != 0; });
  };
  int begin = 0, end = mask.height();
  while (begin < end && !occupied(begin)) ++begin;
  while (end > begin && !occupied(end - 1)) --end;
  return {begin, end};
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
  // Only the rows near the foreground can change: the opening keeps within the
  // foreground's rows, the closing's dilation reaches k/2 rows beyond them, and its erosion
  // does not grow. So k rows around them are computed and every other row is background
  // (the mask borders keep their meaning: rows beyond them still count as in cv::erode).
  const auto [occupied_begin, occupied_end] = occupiedRows(mask);
  const int begin = std::max(0, occupied_begin - k), end = std::min(mask.height(), occupied_end + k);
  if (occupied_begin >= occupied_end) return;  // all background stays so
  squarePass<true>(mask, k, a, scratch.temp, scratch, begin, end);
  squarePass<false>(scratch.temp, k, reflected, mask, scratch, begin, end);
  squarePass<false>(mask, k, a, scratch.temp, scratch, begin, end);
  squarePass<true>(scratch.temp, k, reflected, mask, scratch, begin, end);
}

}  // namespace soccer_vision
