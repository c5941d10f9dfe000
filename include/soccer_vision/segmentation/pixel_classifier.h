// The fast path of the colour table: classifies pixels straight from the camera's
// encoding (bgr8, rgb8, Bayer mosaics without demosaicing), with the block-wise
// illumination adjustment (a gain and an offset per block) folded into the lookup, and
// optional Laplacian sharpening of V. Every result equals
// ColorTable::classify(b, g, r, v_offset, v_gain) (plus the sharpening term when enabled)
// for that pixel: the tables here are a re-indexing of the colour table, never an
// approximation of it.
//
// Label resolution: one label per image pixel for bgr8/rgb8; one label per 2x2 Bayer quad
// (its R, the mean of its two G rounded half up: (G1 + G2 + 1) >> 1, its B) for Bayer
// encodings, i.e. half the image size.
//
// Sharpening (paper §IV), on V = max(b, g, r) of label pixels, before the offset:
//   L(x, y)  = V(x-1, y) + V(x+1, y) + V(x, y-1) + V(x, y+1) - 4 V(x, y), with coordinates
//              outside the label image replaced by the nearest inside (border replicated);
//   V_s      = clamp(V - lround(sharpen * L), 0, 255)   (lround: half away from zero);
//   class    = table.classifyHsv(H, S, ColorTable::adjustedV(V_s, offset, gain))
//              (H, S of the pixel itself),
// i.e. ColorTable::classify with V replaced by V_s. sharpen = 0 is exactly the table.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/segmentation/color_table.h"

namespace soccer_vision {

namespace detail {
struct ClassLookup;  // the re-indexed table, defined in pixel_classifier.cpp
}

enum class PixelLayout { Bgr, Rgb, BayerRggb, BayerBggr, BayerGbrg, BayerGrbg };

// sensor_msgs encoding name -> layout; nullopt for anything else (mono8, 16-bit, yuv...).
std::optional<PixelLayout> pixelLayoutForEncoding(const std::string& encoding);
// Layout -> its sensor_msgs encoding name ("bayer_rggb8"); the inverse of the above.
const char* encodingForPixelLayout(PixelLayout layout);
inline bool isBayer(PixelLayout layout) { return layout != PixelLayout::Bgr && layout != PixelLayout::Rgb; }
// Label image size for an image of `image_size` in this layout.
cv::Size labelSize(cv::Size image_size, PixelLayout layout);

// Where the colours of label row `y` lie in an image of this layout: label pixel x has
// B = b[x * step], G = (g1[x * step] + g2[x * step] + 1) >> 1, R = r[x * step] (for
// bgr8/rgb8 g1 == g2). Unchecked (hot path): the image must fit the layout and y be a row
// of its label image.
struct LabelRow {
  const std::uint8_t *b, *g1, *g2, *r;
  int step;
};
// Where the four sensor sites of a Bayer quad lie, relative to its top-left pixel, in
// LabelRow's order; all (0, 0) for bgr8/rgb8.
struct QuadSites {
  cv::Point b, g1, g2, r;
};
inline QuadSites quadSites(PixelLayout layout) {
  switch (layout) {
    case PixelLayout::BayerRggb:
      return {{1, 1}, {1, 0}, {0, 1}, {0, 0}};
    case PixelLayout::BayerBggr:
      return {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    case PixelLayout::BayerGbrg:
      return {{1, 0}, {0, 0}, {1, 1}, {0, 1}};
    case PixelLayout::BayerGrbg:
      return {{0, 1}, {0, 0}, {1, 1}, {1, 0}};
    default:
      return {};
  }
}
// (Inline: it is called once per row of every rectangle classified.)
inline LabelRow labelRow(const cv::Mat& image, PixelLayout layout, int y) {
  if (!isBayer(layout)) {
    const std::uint8_t* p = image.ptr<std::uint8_t>(y);
    return layout == PixelLayout::Bgr ? LabelRow{p, p + 1, p + 1, p + 2, 3}
                                      : LabelRow{p + 2, p + 1, p + 1, p, 3};
  }
  const std::uint8_t* rows[2] = {image.ptr<std::uint8_t>(2 * y), image.ptr<std::uint8_t>(2 * y + 1)};
  const QuadSites s = quadSites(layout);
  return {rows[s.b.y] + s.b.x, rows[s.g1.y] + s.g1.x, rows[s.g2.y] + s.g2.x, rows[s.r.y] + s.r.x, 2};
}
// Throws std::invalid_argument unless the image fits the layout (see FrameClassifier).
void checkImageFitsLayout(const cv::Mat& image, PixelLayout layout);

// Which classes produce regions (a bit per ColorClass value).
using ClassMask = std::uint32_t;
constexpr ClassMask classBit(ColorClass c) { return ClassMask(1) << static_cast<int>(c); }
ClassMask markerClassMask();  // Blue .. Orange

// Per 32x32-pixel block of the image (the paper's blocks), the illumination adjustment of
// V before the lookup: V' = ColorTable::adjustedV(V, offset, gain). Each a matrix of
// ceil(h/32) x ceil(w/32) blocks or empty. `offsets`: CV_16SC1, the paper's round(k * Δv);
// empty = all zero. `gains`: CV_16UC1, fixed point (ColorTable::kUnitGain = 1), the
// normalised-V scale; empty = all unit.
struct BlockOffsets {
  static constexpr int kBlockSize = 32;  // image pixels
  cv::Mat offsets;
  cv::Mat gains;
};

// Immutable after construction: shared by threads, swapped atomically as a whole.
// Construction re-indexes the table (~4 MB, ~0.1 s): do it when a table is loaded.
// Throws std::invalid_argument for a table with more than 65536 distinct V columns
// (impossible with the default 90 x 16 bins).
class PixelClassifier {
 public:
  explicit PixelClassifier(std::shared_ptr<const ColorTable> table);
  const ColorTable& table() const { return *table_; }
  std::shared_ptr<const ColorTable> tableShared() const { return table_; }

  // One colour (b, g, r) with a V offset and gain; equals
  // table().classify(b, g, r, v_offset, v_gain).
  ColorClass classify(std::uint8_t b, std::uint8_t g, std::uint8_t r, int v_offset,
                      int v_gain = ColorTable::kUnitGain) const;

 private:
  friend class FrameClassifier;
  std::shared_ptr<const ColorTable> table_;
  std::shared_ptr<const detail::ClassLookup> lookup_;
};

// One frame bound to a classifier: classifies rectangles or grid points of it on demand,
// so segmentation only touches the pixels it needs.
class FrameClassifier {
 public:
  // `image` and `classifier` must stay alive and unchanged while this object is used
  // (`offsets` is shared, not copied: leave it unchanged too). Throws
  // std::invalid_argument when its type does not fit the layout (CV_8UC3 for Bgr/Rgb,
  // CV_8UC1 with even width and height for Bayer), when `offsets.offsets` or
  // `offsets.gains` is neither empty nor of its type (CV_16SC1, CV_16UC1) on the image's
  // block grid, or when sharpen < 0.
  FrameClassifier(const PixelClassifier& classifier, const cv::Mat& image, PixelLayout layout,
                  const BlockOffsets& offsets, double sharpen = 0.0);

  cv::Size labelSize() const;
  // Labels (ColorClass values) of every label pixel in `rect` (label coordinates, inside
  // the label image) written to `out`, a CV_8UC1 of rect.size() (may be a view into a
  // larger matrix; allocated when it is not of that size and type). Throws
  // std::invalid_argument for a rect outside the label image.
  // `keep`: labels of other classes are written as None (the region extractor needs only
  // the marker classes); a pixel whose colour cube holds no kept class is then settled by
  // one lookup instead of three. All classes by default.
  void classify(const cv::Rect& rect, cv::Mat& out, ClassMask keep = ~ClassMask(0)) const;
  // The label of one label pixel, as classify would write it (for tests of a few pixels
  // around a point). Throws std::invalid_argument outside the label image.
  std::uint8_t classifyPixel(int x, int y, ClassMask keep = ~ClassMask(0)) const;
  // Label pixels (x, y) in `rect` with x % stride == 0 and y % stride == 0 whose class is
  // in `classes`, appended to `hits` row by row. Most pixels are rejected by a 4x4x4
  // colour-cube test before the full lookup. Throws std::invalid_argument for stride < 1
  // or a rect outside the label image.
  void scanGrid(const cv::Rect& rect, int stride, ClassMask classes, std::vector<cv::Point>& hits) const;
  // The same for the label pixels x_begin, x_begin + step, ... < x_end of row y (e.g. a
  // checkerboard's points). Throws std::invalid_argument for step < 1 or points outside
  // the label image.
  void scanPoints(int y, int x_begin, int x_end, int step, ClassMask classes,
                  std::vector<cv::Point>& hits) const;
  // Colour of a label pixel as classified (BGR; a Bayer quad's R, mean G, B), for
  // sub-pixel weighting of region edges.
  cv::Vec3b colorAt(int x, int y) const;
  // Where the colours of label row `y` lie (labelRow of the image), for reading many
  // colours of a row without colorAt's per-pixel checks. Throws std::invalid_argument for
  // a row outside the label image.
  LabelRow row(int y) const;
  PixelLayout layout() const { return layout_; }
  // V (max channel) of a label pixel as looked up: sharpened (when enabled), then
  // adjusted by its block's gain and offset (ColorTable::adjustedV). For debugging/tests.
  int adaptedV(int x, int y) const;

 private:
  int sharpenedV(int x, int y) const;
  void scanRowPoints(int y, int x0, int x1, int step, ClassMask classes,
                     std::vector<cv::Point>& hits) const;  // unchecked
  void classifySharpened(const cv::Rect& rect, cv::Mat& out, ClassMask keep) const;
  int adjustedVAt(int x, int y, int v) const;
  void checkRect(const cv::Rect& rect) const;

  const PixelClassifier& classifier_;
  cv::Mat image_;
  PixelLayout layout_;
  cv::Size label_size_;
  cv::Mat offsets_;  // CV_16SC1 per block (shares the caller's data); zeros when none given
  cv::Mat gains_;    // CV_16UC1 per block (shares the caller's data); unit when none given
  int block_shift_;  // log2 of the block side in label pixels: 32 image pixels
  std::vector<std::int16_t> sharpen_terms_;  // lround(sharpen * L) for L = -1020 .. 1020; empty: off
};

}  // namespace soccer_vision
