// The fast path re-indexes the colour table instead of converting pixels to HSV:
//
//  * H and S of a pixel do not depend on the V offset, only V's bin does. So every 24-bit
//    colour is mapped once, with the table's own bgrToHsv/hBin/sBin, to the *V column* of
//    its HS cell: the 256 classes of that cell for V' = 0..255, with V' the adjusted V
//    (ColorTable::adjustedV: V scaled by the block's gain, plus its offset, clamped).
//    HS cells with equal columns share one (most of the HS plane is all None; a calibrated
//    table has tens of distinct columns), so the lookup is
//    class = column[id(b, g, r)][adjustedV(max(b, g, r), offset, gain)].
//  * id(b, g, r) is a two-level table: the 4x4x4 colour cube (6 bits per channel, 2^18
//    uint32) gives a block of 64 column ids (uint16) for the colours inside it. A cube
//    whose colours all share one column points at that column's shared uniform block; only
//    cubes across an HS cell border own a block (~6 % of them): ~1 MB + ~2 MB instead of a
//    flat 2^24 table's 32 MB, so lookups stay in L2/L3 even with several cameras.
//  * Per cube, the classes any of its colours can take at any V (2^18 uint16, 512 KB; the
//    carpet's few cubes stay in L1) reject most pixels before the lookup proper. A
//    generalised table gives the carpet's colours a marker class too, at a higher V' (a
//    green marker brighter than the carpet), so the AVX-512 kernels test the V' band as
//    well: per cube, the bands in which a marker class occurs, and for the scan first, in
//    registers, per coarse cell (512) the lowest and highest of them.
#include "soccer_vision/segmentation/pixel_classifier.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "soccer_vision/segmentation/simd_kernels.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SV_HAVE_AVX512_KERNELS 1
#endif

namespace soccer_vision {
namespace detail {

struct ClassLookup {
  static constexpr int kLevels = 256;
  static constexpr int kCubeShift = 2;  // 6 bits per channel
  static constexpr int kCubeBits = 8 - kCubeShift;
  static constexpr int kCubeColors = 1 << (3 * kCubeShift);

  std::vector<std::uint32_t> cube_block;     // cube -> block of its colours' column ids
  std::vector<std::uint16_t> block_columns;  // block * 64 + colour in cube -> column id
  std::vector<std::uint8_t> column_classes;  // column id * 256 + V' -> ColorClass
  std::vector<std::uint16_t> cube_classes;   // cube -> ClassMask of its possible classes
  // Bands of 16 adjusted levels V' (bit k: V' in [16k, 16k + 15]) in which some colour of a
  // cube takes a marker class (markerClassMask). V' matters: a green marker's cells lie
  // above the carpet's in V, and without it most carpet points pass a test of colour alone.
  static constexpr int kBandShift = 4;
  std::vector<std::uint16_t> cube_marker_bands;
  // Per coarse cell (3 bits per channel: b >> 5, g >> 5, r >> 5), the lowest and highest
  // band of its cubes' marker bands (low and high nibble; 0x0F: none): the scan's first
  // test, in registers. It rejects ~95 % of the carpet's points, which then touch no table.
  static constexpr int kCoarseShift = 5;
  static constexpr int kCoarseCells = 1 << (3 * (8 - kCoarseShift));
  std::uint8_t coarse_marker_range[kCoarseCells] = {};
  // The same per medium cell (4 bits per channel: 4 KB, stays in L1/L2 between frames where
  // cube_marker_bands does not): the AVX-512 scan's second test, before cubeBandTest.
  static constexpr int kMediumShift = 4;
  static constexpr int kMediumCells = 1 << (3 * (8 - kMediumShift));
  std::vector<std::uint8_t> medium_marker_range;

  static std::size_t inCube(int b, int g, int r) {
    constexpr int low = (1 << kCubeShift) - 1;
    return static_cast<std::size_t>(((b & low) << (2 * kCubeShift)) | ((g & low) << kCubeShift) | (r & low));
  }
  static std::size_t cubeIndex(int b, int g, int r) {
    return (static_cast<std::size_t>(b >> kCubeShift) << (2 * kCubeBits)) |
           (static_cast<std::size_t>(g >> kCubeShift) << kCubeBits) |
           static_cast<std::size_t>(r >> kCubeShift);
  }
  static int mediumIndex(int b, int g, int r) {
    constexpr int bits = 8 - kMediumShift;
    return ((b >> kMediumShift) << (2 * bits)) | ((g >> kMediumShift) << bits) | (r >> kMediumShift);
  }
  static int coarseIndex(int b, int g, int r) {
    constexpr int bits = 8 - kCoarseShift;
    return ((b >> kCoarseShift) << (2 * bits)) | ((g >> kCoarseShift) << bits) | (r >> kCoarseShift);
  }
  bool mayBeIn(int b, int g, int r, ClassMask classes) const {
    return cube_classes[cubeIndex(b, g, r)] & classes;
  }
  // adapted_v in 0..255.
  std::uint8_t classAt(int b, int g, int r, int adapted_v) const {
    const std::size_t block = cube_block[cubeIndex(b, g, r)];
    const std::size_t column = block_columns[block * kCubeColors + inCube(b, g, r)];
    return column_classes[column * kLevels + static_cast<std::size_t>(adapted_v)];
  }
};

}  // namespace detail

namespace {

using detail::ClassLookup;
static_assert(kNumColorClasses <= 16, "cube masks are 16 bits");

constexpr int clampV(int v) { return v < 0 ? 0 : v > 255 ? 255 : v; }
// ColorTable::adjustedV for the hot loops (same formula, no call).
constexpr int adjust(int v, int offset, int gain) { return clampV(((v * gain + 128) >> 8) + offset); }
constexpr int maxOf(int b, int g, int r) { return std::max(b, std::max(g, r)); }
constexpr int kMaxLaplacian = 4 * 255;

// Columns: the table's V bins expanded to 256 levels, equal columns shared.
struct Columns {
  std::vector<std::uint16_t> of_hs_cell;
  std::vector<std::uint8_t> classes;
  std::vector<std::uint16_t> masks;
  std::vector<std::uint16_t> marker_bands;  // as ClassLookup::cube_marker_bands'
};

Columns buildColumns(const ColorTable& table) {
  const ColorTableParams& p = table.params();
  const std::size_t hs_cells = static_cast<std::size_t>(p.h_bins) * p.s_bins;
  const std::vector<ColorClass>& cells = table.cells();
  Columns columns;
  columns.of_hs_cell.resize(hs_cells);
  std::map<std::vector<ColorClass>, std::uint16_t> ids;
  for (std::size_t hs = 0; hs < hs_cells; ++hs) {
    std::vector<ColorClass> bins(cells.begin() + static_cast<std::ptrdiff_t>(hs * p.v_bins),
                                 cells.begin() + static_cast<std::ptrdiff_t>((hs + 1) * p.v_bins));
    auto [it, added] = ids.emplace(std::move(bins), static_cast<std::uint16_t>(ids.size()));
    if (added) {
      if (ids.size() > 65536) {
        throw std::invalid_argument(
            "PixelClassifier: the colour table has more than 65536 distinct V columns");
      }
      std::uint16_t mask = 0;
      std::uint16_t marker_bands = 0;
      for (int v = 0; v < ClassLookup::kLevels; ++v) {
        const ColorClass c = it->first[static_cast<std::size_t>(table.vBin(v))];
        columns.classes.push_back(static_cast<std::uint8_t>(c));
        mask |= static_cast<std::uint16_t>(classBit(c));
        if (classBit(c) & markerClassMask())
          marker_bands |= static_cast<std::uint16_t>(1u << (v >> ClassLookup::kBandShift));
      }
      columns.masks.push_back(mask);
      columns.marker_bands.push_back(marker_bands);
    }
    columns.of_hs_cell[hs] = it->second;
  }
  return columns;
}

// Every 24-bit colour -> its column, through the table's own HSV conversion and binning,
// cube by cube. bgrToHsv's hue depends only on which channel is the maximum, max - min and
// the difference of the other two, and its saturation only on max and max - min:
// memoising on those keys evaluates the definition ~200k times instead of 2^24.
std::shared_ptr<const ClassLookup> buildLookup(const ColorTable& table) {
  const Columns columns = buildColumns(table);
  const int s_bins = table.params().s_bins;

  std::vector<std::int16_t> s_bin(256 * 256);  // [max][range]
  for (int max = 0; max < 256; ++max) {
    for (int range = 0; range <= max; ++range) {
      const auto lo = static_cast<std::uint8_t>(max - range);
      s_bin[max * 256 + range] =
          static_cast<std::int16_t>(table.sBin(bgrToHsv(static_cast<std::uint8_t>(max), lo, lo).s));
    }
  }
  std::vector<std::int16_t> h_bin(3 * 256 * 511, -1);  // [sector][range][difference + 255], lazily

  auto column_of = [&](int b, int g, int r) {
    const int max = maxOf(b, g, r);
    const int range = max - std::min(b, std::min(g, r));
    // Same branch order as bgrToHsv.
    const int sector = max == r ? 0 : max == g ? 1 : 2;
    const int difference = sector == 0 ? g - b : sector == 1 ? b - r : r - g;
    std::int16_t& hb = h_bin[(sector * 256 + range) * 511 + difference + 255];
    if (hb < 0) {
      hb = static_cast<std::int16_t>(table.hBin(
          bgrToHsv(static_cast<std::uint8_t>(b), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(r))
              .h));
    }
    return columns.of_hs_cell[static_cast<std::size_t>(hb) * s_bins +
                              static_cast<std::size_t>(s_bin[max * 256 + range])];
  };

  constexpr int side = 1 << ClassLookup::kCubeShift, cubes_per_channel = 1 << ClassLookup::kCubeBits;
  const std::size_t n_columns = columns.masks.size();
  auto lookup = std::make_shared<ClassLookup>();
  lookup->column_classes = columns.classes;
  lookup->cube_block.resize(std::size_t(1) << (3 * ClassLookup::kCubeBits));
  lookup->cube_classes.resize(lookup->cube_block.size());
  lookup->cube_marker_bands.resize(lookup->cube_block.size());
  // Blocks 0 .. n_columns - 1: one uniform block per column.
  for (std::size_t c = 0; c < n_columns; ++c) {
    lookup->block_columns.insert(lookup->block_columns.end(), ClassLookup::kCubeColors,
                                 static_cast<std::uint16_t>(c));
  }
  std::uint16_t ids[ClassLookup::kCubeColors];
  std::vector<std::uint16_t> coarse_bands(ClassLookup::kCoarseCells);  // OR of their cubes' marker bands
  std::vector<std::uint16_t> medium_bands(ClassLookup::kMediumCells);
  for (int cb = 0; cb < cubes_per_channel; ++cb) {
    for (int cg = 0; cg < cubes_per_channel; ++cg) {
      for (int cr = 0; cr < cubes_per_channel; ++cr) {
        const int b0 = cb * side, g0 = cg * side, r0 = cr * side;
        std::uint16_t mask = 0, marker_bands = 0;
        bool uniform = true;
        for (int db = 0; db < side; ++db) {
          for (int dg = 0; dg < side; ++dg) {
            for (int dr = 0; dr < side; ++dr) {
              const std::size_t i = ClassLookup::inCube(db, dg, dr);
              ids[i] = column_of(b0 + db, g0 + dg, r0 + dr);
              mask = static_cast<std::uint16_t>(mask | columns.masks[ids[i]]);
              marker_bands |= columns.marker_bands[ids[i]];
              uniform = uniform && ids[i] == ids[0];
            }
          }
        }
        const std::size_t cube = ClassLookup::cubeIndex(b0, g0, r0);
        lookup->cube_classes[cube] = mask;
        lookup->cube_marker_bands[cube] = marker_bands;
        coarse_bands[ClassLookup::coarseIndex(b0, g0, r0)] |= marker_bands;
        medium_bands[static_cast<std::size_t>(ClassLookup::mediumIndex(b0, g0, r0))] |= marker_bands;
        if (uniform) {
          lookup->cube_block[cube] = ids[0];
        } else {
          lookup->cube_block[cube] =
              static_cast<std::uint32_t>(lookup->block_columns.size() / ClassLookup::kCubeColors);
          lookup->block_columns.insert(lookup->block_columns.end(), ids, ids + ClassLookup::kCubeColors);
        }
      }
    }
  }
  for (int cell = 0; cell < ClassLookup::kCoarseCells; ++cell) {
    const unsigned bands = coarse_bands[static_cast<std::size_t>(cell)];
    lookup->coarse_marker_range[cell] =
        bands ? static_cast<std::uint8_t>(__builtin_ctz(bands) | (31 - __builtin_clz(bands)) << 4) : 0x0F;
  }
  lookup->medium_marker_range.resize(ClassLookup::kMediumCells + 3);  // padded for 4-byte gathers
  for (int cell = 0; cell < ClassLookup::kMediumCells; ++cell) {
    const unsigned bands = medium_bands[static_cast<std::size_t>(cell)];
    lookup->medium_marker_range[static_cast<std::size_t>(cell)] =
        bands ? static_cast<std::uint8_t>(__builtin_ctz(bands) | (31 - __builtin_clz(bands)) << 4) : 0x0F;
  }
  // The AVX-512 scan gathers 4 bytes per entry: padding keeps the last entry's read inside.
  lookup->cube_classes.push_back(0);
  lookup->cube_marker_bands.push_back(0);
  lookup->block_columns.push_back(0);  // the same for the AVX-512 classification's gathers
  lookup->column_classes.insert(lookup->column_classes.end(), 3, 0);
  lookup->block_columns.shrink_to_fit();
  return lookup;
}

// Whether `classes` holds marker classes only: the V' band tables know those alone.
bool onlyMarkerClasses(ClassMask classes) { return (classes & ~markerClassMask()) == 0; }

// Label rows of one frame read with a compile-time pixel step (3: bgr/rgb, 2: Bayer).
template <int Step>
struct Pixels {
  explicit Pixels(const LabelRow& row) : row(row) {}
  int b(int x) const { return row.b[x * Step]; }
  int g(int x) const {
    if constexpr (Step == 3) return row.g1[x * Step];  // one green: g1 == g2
    return (row.g1[x * Step] + row.g2[x * Step] + 1) >> 1;
  }
  int r(int x) const { return row.r[x * Step]; }
  LabelRow row;
};

// Any layout, step known at run time: for the less travelled paths.
int greenAt(const LabelRow& row, int x) { return (row.g1[x * row.step] + row.g2[x * row.step] + 1) >> 1; }
int valueAt(const LabelRow& row, int x) {
  return maxOf(row.b[x * row.step], greenAt(row, x), row.r[x * row.step]);
}

}  // namespace

// ---------------------------------------------------------------- layouts

namespace {

// The one map between sensor_msgs encodings and layouts, both ways.
constexpr std::pair<const char*, PixelLayout> kLayoutEncodings[] = {
    {"bgr8", PixelLayout::Bgr},
    {"rgb8", PixelLayout::Rgb},
    {"bayer_rggb8", PixelLayout::BayerRggb},
    {"bayer_bggr8", PixelLayout::BayerBggr},
    {"bayer_gbrg8", PixelLayout::BayerGbrg},
    {"bayer_grbg8", PixelLayout::BayerGrbg},
};

}  // namespace

std::optional<PixelLayout> pixelLayoutForEncoding(const std::string& encoding) {
  for (const auto& [name, layout] : kLayoutEncodings) {
    if (encoding == name) return layout;
  }
  return std::nullopt;
}

const char* encodingForPixelLayout(PixelLayout layout) {
  for (const auto& [name, l] : kLayoutEncodings) {
    if (l == layout) return name;
  }
  return "?";  // not a PixelLayout value
}

cv::Size labelSize(cv::Size image_size, PixelLayout layout) {
  return isBayer(layout) ? cv::Size(image_size.width / 2, image_size.height / 2) : image_size;
}

ClassMask markerClassMask() {
  ClassMask mask = 0;
  for (int c = static_cast<int>(ColorClass::Blue); c <= static_cast<int>(ColorClass::Orange); ++c) {
    mask |= classBit(static_cast<ColorClass>(c));
  }
  return mask;
}

void checkImageFitsLayout(const cv::Mat& image, PixelLayout layout) {
  if (isBayer(layout)) {
    if (image.type() != CV_8UC1 || image.cols % 2 != 0 || image.rows % 2 != 0) {
      throw std::invalid_argument("a Bayer image must be CV_8UC1 with even width and height");
    }
  } else if (image.type() != CV_8UC3) {
    throw std::invalid_argument("a bgr8/rgb8 image must be CV_8UC3");
  }
}

// ---------------------------------------------------------------- PixelClassifier

PixelClassifier::PixelClassifier(std::shared_ptr<const ColorTable> table) : table_(std::move(table)) {
  if (!table_) throw std::invalid_argument("PixelClassifier: no colour table");
  lookup_ = buildLookup(*table_);
}

ColorClass PixelClassifier::classify(std::uint8_t b, std::uint8_t g, std::uint8_t r, int v_offset,
                                     int v_gain) const {
  return static_cast<ColorClass>(
      lookup_->classAt(b, g, r, ColorTable::adjustedV(maxOf(b, g, r), v_offset, v_gain)));
}

// ---------------------------------------------------------------- FrameClassifier

FrameClassifier::FrameClassifier(const PixelClassifier& classifier, const cv::Mat& image, PixelLayout layout,
                                 const BlockOffsets& offsets, double sharpen)
    : classifier_(classifier),
      image_(image),
      layout_(layout),
      label_size_(soccer_vision::labelSize(image.size(), layout)),
      block_shift_(isBayer(layout) ? 4 : 5) {
  checkImageFitsLayout(image, layout);
  static_assert(BlockOffsets::kBlockSize == 32, "block_shift_ assumes 32-pixel blocks");
  const cv::Size blocks((image.cols + 31) / 32, (image.rows + 31) / 32);
  auto per_block = [&](const cv::Mat& given, int type, const char* what, double none) {
    if (given.empty()) return cv::Mat(blocks, type, cv::Scalar(none));
    if (given.type() != type || given.size() != blocks) {
      throw std::invalid_argument(std::string("FrameClassifier: ") + what + " must be " +
                                  (type == CV_16SC1 ? "CV_16SC1" : "CV_16UC1") + " of " +
                                  std::to_string(blocks.height) + " x " + std::to_string(blocks.width) +
                                  " blocks");
    }
    return given;
  };
  offsets_ = per_block(offsets.offsets, CV_16SC1, "offsets", 0);
  gains_ = per_block(offsets.gains, CV_16UC1, "gains", ColorTable::kUnitGain);
  if (!(sharpen >= 0.0)) throw std::invalid_argument("FrameClassifier: sharpen must be >= 0");
  if (sharpen > 0.0) {
    sharpen_terms_.resize(2 * kMaxLaplacian + 1);
    for (int l = -kMaxLaplacian; l <= kMaxLaplacian; ++l) {
      // Terms beyond ±510 saturate every V: clamping them first keeps lround in range.
      sharpen_terms_[l + kMaxLaplacian] =
          static_cast<std::int16_t>(std::lround(std::clamp(sharpen * l, -1000.0, 1000.0)));
    }
  }
}

cv::Size FrameClassifier::labelSize() const { return label_size_; }

void FrameClassifier::checkRect(const cv::Rect& rect) const {
  if (rect.x < 0 || rect.y < 0 || rect.width < 0 || rect.height < 0 ||
      rect.x + rect.width > label_size_.width || rect.y + rect.height > label_size_.height) {
    throw std::invalid_argument("FrameClassifier: rect outside the label image");
  }
}

int FrameClassifier::adjustedVAt(int x, int y, int v) const {
  const int bx = x >> block_shift_, by = y >> block_shift_;
  return adjust(v, offsets_.at<std::int16_t>(by, bx), gains_.at<std::uint16_t>(by, bx));
}

int FrameClassifier::sharpenedV(int x, int y) const {
  auto v = [&](int px, int py) {
    return valueAt(labelRow(image_, layout_, std::clamp(py, 0, label_size_.height - 1)),
                   std::clamp(px, 0, label_size_.width - 1));
  };
  const int centre = v(x, y);
  if (sharpen_terms_.empty()) return centre;
  const int laplacian = v(x - 1, y) + v(x + 1, y) + v(x, y - 1) + v(x, y + 1) - 4 * centre;
  return clampV(centre - sharpen_terms_[laplacian + kMaxLaplacian]);
}

int FrameClassifier::adaptedV(int x, int y) const {
  checkRect({x, y, 1, 1});
  return adjustedVAt(x, y, sharpenedV(x, y));
}

cv::Vec3b FrameClassifier::colorAt(int x, int y) const {
  checkRect({x, y, 1, 1});
  const LabelRow row = labelRow(image_, layout_, y);
  return {row.b[x * row.step], static_cast<std::uint8_t>(greenAt(row, x)), row.r[x * row.step]};
}

std::uint8_t FrameClassifier::classifyPixel(int x, int y, ClassMask keep) const {
  checkRect({x, y, 1, 1});
  const ClassLookup& lookup = *classifier_.lookup_;
  const LabelRow row = labelRow(image_, layout_, y);
  const int b = row.b[x * row.step], g = greenAt(row, x), r = row.r[x * row.step];
  // A cube holding none of `keep` gives None, as classify writes it (with every class
  // kept, every cube passes: its mask holds at least None).
  if (!lookup.mayBeIn(b, g, r, keep)) return 0;
  const int v = sharpen_terms_.empty() ? maxOf(b, g, r) : sharpenedV(x, y);
  const std::uint8_t label = lookup.classAt(b, g, r, adjustedVAt(x, y, v));
  return keep & (ClassMask(1) << label) ? label : 0;
}

LabelRow FrameClassifier::row(int y) const {
  checkRect({0, y, label_size_.width, 1});
  return labelRow(image_, layout_, y);
}

namespace {

// The block adjustments of one label row.
struct RowAdjustment {
  const std::int16_t* offsets;
  const std::uint16_t* gains;
  int block_shift;
  int blocks;  // of the row: entries of offsets and gains
  int operator()(int x, int v) const { return adjust(v, offsets[x >> block_shift], gains[x >> block_shift]); }
};

// Labels of label row `row` for x in [x0, x1).
template <int Step>
void classifyRow(const ClassLookup& lookup, const LabelRow& row, const RowAdjustment& adjusted, int x0,
                 int x1, std::uint8_t* out) {
  const Pixels<Step> px(row);
  for (int x = x0; x < x1; ++x) {
    const int b = px.b(x), g = px.g(x), r = px.r(x);
    *out++ = lookup.classAt(b, g, r, adjusted(x, maxOf(b, g, r)));
  }
}

// The colour cube of a pixel from unsigned channels: ClassLookup::cubeIndex in 32-bit
// arithmetic (immediate masks, no sign extensions), for the hot loops below.
inline std::size_t cubeOf(unsigned b, unsigned g, unsigned r) {
  static_assert(ClassLookup::kCubeShift == 2 && ClassLookup::kCubeBits == 6, "cubeOf assumes 6-bit cubes");
  return ((b << 10) & 0x3F000u) | ((g << 4) & 0xFC0u) | (r >> 2);
}

// The same, other classes than `keep` written as None. The tables' pointers live in
// locals: stores through `out` could alias them as far as the compiler knows.
template <int Step>
void classifyRowKeeping(const ClassLookup& lookup, const LabelRow& row, const RowAdjustment& adjusted, int x0,
                        int x1, ClassMask keep, std::uint8_t* out) {
  const std::uint16_t* cube_classes = lookup.cube_classes.data();
  const std::uint16_t* marker_bands = lookup.cube_marker_bands.data();
  const bool markers_only = onlyMarkerClasses(keep);
  const Pixels<Step> px(row);
  for (int x = x0; x < x1; ++x) {
    const int b = px.b(x), g = px.g(x), r = px.r(x);
    const std::size_t cube = cubeOf(unsigned(b), unsigned(g), unsigned(r));
    std::uint8_t label = 0;
    if (cube_classes[cube] & keep) {
      const int level = adjusted(x, maxOf(b, g, r));
      if (!markers_only || (marker_bands[cube] >> (level >> ClassLookup::kBandShift) & 1)) {
        label = lookup.classAt(b, g, r, level);
        if (!(keep & (ClassMask(1) << label))) label = 0;
      }
    }
    *out++ = label;
  }
}

// A grid point whose cube may hold a wanted class: the full lookup, out of the scan's
// loop so that the loop keeps its few values in registers.
[[gnu::noinline]] void checkGridPoint(const ClassLookup& lookup, const RowAdjustment& adjusted, int x, int y,
                                      unsigned b, unsigned g, unsigned r, ClassMask classes,
                                      std::vector<cv::Point>& hits) {
  const int label = lookup.classAt(int(b), int(g), int(r), adjusted(x, maxOf(int(b), int(g), int(r))));
  if (classes & (ClassMask(1) << label)) hits.push_back(cv::Point(x, y));
}

// Grid points of a row: most are rejected by their cube, so that path is kept short
// (pointers in registers, one index step per point).
template <int Step>
void scanRow(const ClassLookup& lookup, const LabelRow& row, const RowAdjustment& adjusted, int y, int x0,
             int x1, int stride, ClassMask classes, std::vector<cv::Point>& hits) {
  const std::uint16_t* cube_classes = lookup.cube_classes.data();
  const std::uint16_t* marker_bands = lookup.cube_marker_bands.data();
  const bool markers_only = onlyMarkerClasses(classes);
  const std::uint8_t *pb = row.b, *pg1 = row.g1, *pg2 = row.g2, *pr = row.r;
  const std::size_t step = static_cast<std::size_t>(stride) * Step;
  std::size_t i = static_cast<std::size_t>(x0) * Step;
  for (int x = x0; x < x1; x += stride, i += step) {
    const unsigned b = pb[i], r = pr[i];
    const unsigned g = Step == 3 ? pg1[i] : (pg1[i] + pg2[i] + 1u) >> 1;  // bgr8/rgb8: one green
    const std::size_t cube = cubeOf(b, g, r);
    if (!(cube_classes[cube] & classes)) continue;
    // The V' band, as the AVX-512 scan tests it (ClassLookup::cube_marker_bands).
    if (markers_only &&
        !(marker_bands[cube] >> (adjusted(x, maxOf(int(b), int(g), int(r))) >> ClassLookup::kBandShift) & 1))
      continue;
    checkGridPoint(lookup, adjusted, x, y, b, g, r, classes, hits);
  }
}

#ifdef SV_HAVE_AVX512_KERNELS
// An AVX-512 version of scanRow, chosen at run time (the build targets plain x86-64): up to
// 16 grid points per step. The image bytes come from two masked 64-byte loads (never past
// the points' own bytes) and a byte permutation, not a gather: the scan is the first touch
// of those bytes, and Zen 4's gathers stall on such misses. Most points (carpet) are then
// rejected by a test in registers (rangeTest, ClassLookup::coarse_marker_range) without
// touching the tables.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12's intrinsics headers
#pragma GCC diagnostic ignored "-Wuninitialized"        // the same (their masked 16-bit loads)
#define SV_AVX512 __attribute__((target("avx512f,avx512bw,avx512vl,avx512vbmi")))

struct Colours {
  __m512i b, g, r;  // one point per 32-bit lane
};

SV_AVX512 inline __m512i lowByte(__m512i v) { return _mm512_and_si512(v, _mm512_set1_epi32(0xFF)); }
// Byte `shift / 8` of each lane.
SV_AVX512 inline __m512i byteOf(__m512i v, int shift) {
  return lowByte(_mm512_srlv_epi32(v, _mm512_set1_epi32(shift)));
}
SV_AVX512 inline __mmask16 firstLanes(int n) {
  return static_cast<__mmask16>(n >= 16 ? 0xFFFF : (1u << n) - 1);
}

// cubeOf per lane.
SV_AVX512 inline __m512i cubeOf(const Colours& c) {
  const __m512i b = _mm512_and_si512(_mm512_slli_epi32(c.b, 10), _mm512_set1_epi32(0x3F000));
  const __m512i g = _mm512_and_si512(_mm512_slli_epi32(c.g, 4), _mm512_set1_epi32(0xFC0));
  return _mm512_or_si512(_mm512_or_si512(b, g), _mm512_srli_epi32(c.r, 2));
}

// The block gains and offsets of lanes at label x `lane_x`, all within the 16 blocks from
// x's on (a step's points lie within 128 bytes of the row: 64 label px, 5 blocks at most).
struct LaneAdjustment {
  __m512i gain, offset;
};
SV_AVX512 inline LaneAdjustment laneAdjustment(const RowAdjustment& adjusted, int x, __m512i lane_x) {
  const int first = x >> adjusted.block_shift;
  const __mmask16 present = firstLanes(adjusted.blocks - first);
  const __m512i gains = _mm512_cvtepu16_epi32(_mm256_maskz_loadu_epi16(present, adjusted.gains + first));
  const __m512i offsets = _mm512_cvtepi16_epi32(_mm256_maskz_loadu_epi16(present, adjusted.offsets + first));
  const __m512i block = _mm512_sub_epi32(_mm512_srl_epi32(lane_x, _mm_cvtsi32_si128(adjusted.block_shift)),
                                         _mm512_set1_epi32(first));
  return {_mm512_permutexvar_epi32(block, gains), _mm512_permutexvar_epi32(block, offsets)};
}

// The adjusted levels V' of the lanes' colours (ColorTable::adjustedV).
SV_AVX512 inline __m512i adjustedLevels(const Colours& c, const LaneAdjustment& adjustment) {
  const __m512i v = _mm512_max_epi32(_mm512_max_epi32(c.b, c.g), c.r);
  const __m512i scaled =
      _mm512_srli_epi32(_mm512_add_epi32(_mm512_mullo_epi32(v, adjustment.gain), _mm512_set1_epi32(128)), 8);
  return _mm512_min_epi32(
      _mm512_max_epi32(_mm512_add_epi32(scaled, adjustment.offset), _mm512_setzero_si512()),
      _mm512_set1_epi32(255));
}

// The lanes' cells of a cube of (256 >> shift)³ cells: (b, g, r) >> shift packed b first.
template <int shift>
SV_AVX512 inline __m512i cubeCells(const Colours& c) {
  constexpr int bits = 8 - shift;
  return _mm512_or_si512(_mm512_or_si512(_mm512_slli_epi32(_mm512_srli_epi32(c.b, shift), 2 * bits),
                                         _mm512_slli_epi32(_mm512_srli_epi32(c.g, shift), bits)),
                         _mm512_srli_epi32(c.r, shift));
}

// The lanes of `live` whose level's band lies within `range` (lowest band in bits 0-3,
// highest in bits 4-7).
SV_AVX512 inline __mmask16 bandWithin(__m512i range, __m512i level, __mmask16 live) {
  const __m512i band = _mm512_srli_epi32(level, ClassLookup::kBandShift);
  const __m512i lowest = _mm512_and_si512(range, _mm512_set1_epi32(0x0F));
  const __m512i highest = _mm512_and_si512(_mm512_srli_epi32(range, 4), _mm512_set1_epi32(0x0F));
  return _mm512_mask_cmple_epi32_mask(_mm512_mask_cmpge_epi32_mask(live, band, lowest), band, highest);
}

// The lanes of `live` whose level's band lies within their coarse cell's marker range
// (ClassLookup::coarse_marker_range, 512 bytes in eight registers).
SV_AVX512 inline __mmask16 rangeTest(const Colours& c, __m512i level, const __m512i (&ranges)[8],
                                     __mmask16 live) {
  const __m512i cell = cubeCells<ClassLookup::kCoarseShift>(c);
  // Byte `cell` of the 512: a byte permutation picks by the low 7 bits within a pair of
  // registers, the quarter (cell >> 7) chooses the pair.
  const __m512i quarter = _mm512_srli_epi32(cell, 7);
  __m512i range = _mm512_permutex2var_epi8(ranges[0], cell, ranges[1]);
  for (int q = 1; q < 4; ++q) {
    const __mmask16 in_quarter = _mm512_cmpeq_epi32_mask(quarter, _mm512_set1_epi32(q));
    range = _mm512_mask_mov_epi32(range, in_quarter,
                                  _mm512_permutex2var_epi8(ranges[2 * q], cell, ranges[2 * q + 1]));
  }
  return bandWithin(range, level, live);
}

// The lanes of `may` whose level's band lies within their medium cell's marker range
// (ClassLookup::medium_marker_range, padded for the 4-byte reads).
SV_AVX512 inline __mmask16 mediumRangeTest(const ClassLookup& lookup, const Colours& c, __m512i level,
                                           __mmask16 may) {
  const __m512i cell = cubeCells<ClassLookup::kMediumShift>(c);
  const __m512i range =
      _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), may, cell, lookup.medium_marker_range.data(), 1);
  return bandWithin(range, level, may);
}

// The lanes of `may` whose cube takes a marker class in the 16-level band of their level
// (ClassLookup::cube_marker_bands; the table is padded for the 4-byte reads).
SV_AVX512 inline __mmask16 cubeBandTest(const ClassLookup& lookup, __m512i cube, __m512i level,
                                        __mmask16 may) {
  const __m512i bands =
      _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), may, cube, lookup.cube_marker_bands.data(), 2);
  const __m512i bit =
      _mm512_sllv_epi32(_mm512_set1_epi32(1), _mm512_srli_epi32(level, ClassLookup::kBandShift));
  return _mm512_mask_test_epi32_mask(may, bands, bit);
}

// The lanes of `may` whose cube takes a class of `wanted` at some V' (ClassLookup::cube_classes).
SV_AVX512 inline __mmask16 cubeClassTest(const ClassLookup& lookup, __m512i cube, __m512i wanted,
                                         __mmask16 may) {
  const __m512i masks =
      _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), may, cube, lookup.cube_classes.data(), 2);
  return _mm512_mask_test_epi32_mask(may, masks, wanted);
}

// Bytes 0 .. n - 1 of two 64-byte loads.
struct TwoLoads {
  __mmask64 low, high;
};
inline TwoLoads firstBytes(int n) {
  return {n >= 64 ? ~0ULL : (1ULL << n) - 1, n > 64 ? ~0ULL >> (128 - n) : 0};
}
// Bytes p[i * span + 0 .. 3] (zero where `bytes_kept` is clear) in lane i, picked from the
// bytes of `loads` from p on.
SV_AVX512 inline __m512i pickBytes(const std::uint8_t* p, TwoLoads loads, __m512i index,
                                   __mmask64 bytes_kept) {
  const __m512i low = _mm512_maskz_loadu_epi8(loads.low, p);
  const __m512i high = _mm512_maskz_loadu_epi8(loads.high, p + 64);
  return _mm512_maskz_permutex2var_epi8(bytes_kept, low, index, high);
}

// pickBytes' index for points `span` bytes apart: lane i picks bytes i * span + 0, 1, 2
// (span <= 41: no carries between the bytes).
SV_AVX512 inline __m512i spanIndex(int span) {
  const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  return _mm512_add_epi32(_mm512_mullo_epi32(lanes, _mm512_set1_epi32(span * 0x01010101)),
                          _mm512_set1_epi32(0x00020100));
}

// The colours of the n (<= 16) label pixels x, x + span / Step, .. of a row, one per lane
// (Bayer: the quad's R, (G1 + G2 + 1) >> 1, B); `index`: spanIndex(span).
template <int Step>
SV_AVX512 inline Colours pickColours(const LabelRow& row, int x, int n, int span, __m512i index) {
  constexpr int kPointBytes = Step == 3 ? 3 : 1;
  const TwoLoads loads = firstBytes((n - 1) * span + kPointBytes);
  if constexpr (Step == 3) {
    const std::uint8_t* base = std::min(row.b, std::min(row.g1, row.r));  // bgr8/rgb8: the pixel's first byte
    const __m512i pixels = pickBytes(base + 3 * x, loads, index, 0x7777777777777777ULL);
    return {byteOf(pixels, 8 * int(row.b - base)), byteOf(pixels, 8 * int(row.g1 - base)),
            byteOf(pixels, 8 * int(row.r - base))};
  } else {
    constexpr __mmask64 kFirstOfFour = 0x1111111111111111ULL;
    const __m512i g1 = pickBytes(row.g1 + 2 * x, loads, index, kFirstOfFour);
    const __m512i g2 = pickBytes(row.g2 + 2 * x, loads, index, kFirstOfFour);
    return {pickBytes(row.b + 2 * x, loads, index, kFirstOfFour),
            _mm512_srli_epi32(_mm512_add_epi32(_mm512_add_epi32(g1, g2), _mm512_set1_epi32(1)), 1),
            pickBytes(row.r + 2 * x, loads, index, kFirstOfFour)};
  }
}

// ---- The scan's first test for two steps at once, one point per 16-bit lane (lanes 0..15
// the first step's, 16..31 the second's): the V' band against coarse_marker_range, as
// adjustedLevels and rangeTest decide it, in half their instructions per point. Most of the
// full frame's points (carpet) end there.

// Where a pair of steps lies: its first points' label x and their counts (n[1] may be 0).
struct StepPair {
  int x[2], n[2];
};

// Bytes 0 .. 127 from p on as two 64-byte registers. Plain loads where all 128 bytes lie
// before the image's end (`end`: the bytes past the step's points are never picked), which
// cost less than masked ones; masked (those bytes zero) at the image's end.
struct Window {
  __m512i low, high;
};
SV_AVX512 inline Window loadWindow(const std::uint8_t* p, TwoLoads loads, const std::uint8_t* end) {
  if (end - p >= 128) return {_mm512_loadu_si512(p), _mm512_loadu_si512(p + 64)};
  return {_mm512_maskz_loadu_epi8(loads.low, p), _mm512_maskz_loadu_epi8(loads.high, p + 64)};
}

// Byte `index` of each 16-bit lane, from the first window in lanes 0..15 and from the second
// in 16..31; the high bytes zero.
SV_AVX512 inline __m512i pickWords(const Window& first, const Window& second, __m512i index) {
  constexpr __mmask64 kFirstLanes = 0x0000000055555555ULL, kSecondLanes = 0x5555555500000000ULL;
  return _mm512_or_si512(_mm512_maskz_permutex2var_epi8(kFirstLanes, first.low, index, first.high),
                         _mm512_maskz_permutex2var_epi8(kSecondLanes, second.low, index, second.high));
}

// The word index of points `span` bytes apart: lane j picks byte (j % 16) * span + `byte`.
SV_AVX512 inline __m512i wordSpanIndex(int span, int byte) {
  const __m512i lanes = _mm512_set_epi16(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 15, 14, 13, 12,
                                         11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  return _mm512_add_epi16(_mm512_mullo_epi16(lanes, _mm512_set1_epi16(static_cast<short>(span))),
                          _mm512_set1_epi16(static_cast<short>(byte)));
}

struct Colours16 {
  __m512i b, g, r;  // one point per 16-bit lane
};

// A channel's bytes (row `p`, Bayer) of each point of a pair of steps.
SV_AVX512 inline __m512i pickChannelPairs(const std::uint8_t* p, int step_bytes, const StepPair& s,
                                          const TwoLoads (&loads)[2], __m512i index,
                                          const std::uint8_t* end) {
  return pickWords(loadWindow(p + step_bytes * s.x[0], loads[0], end),
                   loadWindow(p + step_bytes * s.x[1], loads[1], end), index);
}

// pickColours for a pair of steps; `index`: wordSpanIndex(span, 0); `end`: the image's end.
template <int Step>
SV_AVX512 inline Colours16 pickColourPairs(const LabelRow& row, const StepPair& s, int span, __m512i index,
                                           const std::uint8_t* end) {
  constexpr int kPointBytes = Step == 3 ? 3 : 1;
  const TwoLoads loads[2] = {firstBytes((s.n[0] - 1) * span + kPointBytes),
                             firstBytes(s.n[1] > 0 ? (s.n[1] - 1) * span + kPointBytes : 0)};
  if constexpr (Step == 3) {
    const std::uint8_t* base = std::min(row.b, std::min(row.g1, row.r));  // bgr8/rgb8: the pixel's first byte
    const Window first = loadWindow(base + 3 * s.x[0], loads[0], end);
    const Window second = loadWindow(base + 3 * s.x[1], loads[1], end);
    return {pickWords(first, second,
                      _mm512_add_epi16(index, _mm512_set1_epi16(static_cast<short>(row.b - base)))),
            pickWords(first, second,
                      _mm512_add_epi16(index, _mm512_set1_epi16(static_cast<short>(row.g1 - base)))),
            pickWords(first, second,
                      _mm512_add_epi16(index, _mm512_set1_epi16(static_cast<short>(row.r - base))))};
  } else {
    // (G1 + G2 + 1) >> 1, as the Bayer quads' green.
    return {pickChannelPairs(row.b, 2, s, loads, index, end),
            _mm512_avg_epu16(pickChannelPairs(row.g1, 2, s, loads, index, end),
                             pickChannelPairs(row.g2, 2, s, loads, index, end)),
            pickChannelPairs(row.r, 2, s, loads, index, end)};
  }
}

// Whether the row's gains are below 2^15, the 16-bit V' (adjustedLevelPairs) needs.
SV_AVX512 inline bool gainsFitInt16(const RowAdjustment& adjusted) {
  __mmask32 above = 0;
  for (int i = 0; i < adjusted.blocks; i += 32) {
    const __mmask32 present =
        adjusted.blocks - i >= 32 ? ~__mmask32(0) : (__mmask32(1) << (adjusted.blocks - i)) - 1;
    above |= _mm512_cmpgt_epu16_mask(_mm512_maskz_loadu_epi16(present, adjusted.gains + i),
                                     _mm512_set1_epi16(0x7FFF));
  }
  return above == 0;
}

// The adjusted levels V' of a pair of steps' colours from label x on; `lane_x`: each lane's
// label x less x. (V * gain + 128) >> 8 is mulhrs(V << 7, gain) exactly
// (gains below 2^15), and a saturating add of the offset clamps as the sum would.
SV_AVX512 inline __m512i adjustedLevelPairs(const Colours16& c, const RowAdjustment& adjusted, int x,
                                            __m512i lane_x) {
  const int first = x >> adjusted.block_shift;
  const int blocks = adjusted.blocks - first;
  const __mmask32 present = blocks >= 32 ? ~__mmask32(0) : (__mmask32(1) << blocks) - 1;
  const __m512i block = _mm512_srl_epi16(
      _mm512_add_epi16(lane_x, _mm512_set1_epi16(static_cast<short>(x & ((1 << adjusted.block_shift) - 1)))),
      _mm_cvtsi32_si128(adjusted.block_shift));
  const __m512i gain =
      _mm512_permutexvar_epi16(block, _mm512_maskz_loadu_epi16(present, adjusted.gains + first));
  const __m512i offset =
      _mm512_permutexvar_epi16(block, _mm512_maskz_loadu_epi16(present, adjusted.offsets + first));
  const __m512i v = _mm512_max_epu16(_mm512_max_epu16(c.b, c.g), c.r);
  const __m512i scaled = _mm512_mulhrs_epi16(_mm512_slli_epi16(v, 7), gain);
  return _mm512_min_epi16(_mm512_max_epi16(_mm512_adds_epi16(scaled, offset), _mm512_setzero_si512()),
                          _mm512_set1_epi16(255));
}

// rangeTest for a pair of steps.
SV_AVX512 inline __mmask32 rangeTestPairs(const Colours16& c, __m512i level, const __m512i (&ranges)[8],
                                          __mmask32 live) {
  constexpr int shift = ClassLookup::kCoarseShift, bits = 8 - shift;
  constexpr __mmask64 kLowBytes = 0x5555555555555555ULL;
  const __m512i cell =
      _mm512_or_si512(_mm512_or_si512(_mm512_slli_epi16(_mm512_srli_epi16(c.b, shift), 2 * bits),
                                      _mm512_slli_epi16(_mm512_srli_epi16(c.g, shift), bits)),
                      _mm512_srli_epi16(c.r, shift));
  const __m512i quarter = _mm512_srli_epi16(cell, 7);
  __m512i range = _mm512_maskz_permutex2var_epi8(kLowBytes, ranges[0], cell, ranges[1]);
  for (int q = 1; q < 4; ++q) {
    const __mmask32 in_quarter = _mm512_cmpeq_epi16_mask(quarter, _mm512_set1_epi16(static_cast<short>(q)));
    range = _mm512_mask_mov_epi16(
        range, in_quarter, _mm512_maskz_permutex2var_epi8(kLowBytes, ranges[2 * q], cell, ranges[2 * q + 1]));
  }
  const __m512i band = _mm512_srli_epi16(level, ClassLookup::kBandShift);
  const __m512i lowest = _mm512_and_si512(range, _mm512_set1_epi16(0x0F));
  const __m512i highest = _mm512_srli_epi16(range, 4);
  return _mm512_mask_cmple_epu16_mask(_mm512_mask_cmpge_epu16_mask(live, band, lowest), band, highest);
}

// ClassLookup::classAt of the lanes of `may` (0 elsewhere): the three lookups as gathers
// (the tables are padded for their 4-byte reads), V adjusted by each lane's block.
SV_AVX512 inline __m512i labelsOf(const ClassLookup& lookup, const Colours& c, __m512i cube, __m512i level,
                                  __mmask16 may) {
  const __m512i zero = _mm512_setzero_si512(), three = _mm512_set1_epi32(3);
  const __m512i block = _mm512_mask_i32gather_epi32(zero, may, cube, lookup.cube_block.data(), 4);
  const __m512i in_cube = _mm512_or_si512(_mm512_or_si512(_mm512_slli_epi32(_mm512_and_si512(c.b, three), 4),
                                                          _mm512_slli_epi32(_mm512_and_si512(c.g, three), 2)),
                                          _mm512_and_si512(c.r, three));
  const __m512i column = _mm512_and_si512(
      _mm512_mask_i32gather_epi32(zero, may, _mm512_or_si512(_mm512_slli_epi32(block, 6), in_cube),
                                  lookup.block_columns.data(), 2),
      _mm512_set1_epi32(0xFFFF));
  return _mm512_and_si512(
      _mm512_mask_i32gather_epi32(zero, may, _mm512_or_si512(_mm512_slli_epi32(column, 8), level),
                                  lookup.column_classes.data(), 1),
      _mm512_set1_epi32(0xFF));
}

// The points of one step (label x, x + stride, .., one per lane) whose lanes in `maybe`
// passed the V' band test in registers: the tables decide them, and the hits are appended.
SV_AVX512 inline void lookUpCandidates(const ClassLookup& lookup, const Colours& c, __m512i level,
                                       __mmask16 maybe, int x, int y, int stride, ClassMask classes,
                                       std::vector<cv::Point>& hits) {
  const bool markers_only = onlyMarkerClasses(classes);
  const __m512i wanted = _mm512_set1_epi32(static_cast<int>(classes & 0xFFFF));
  // The few that pass (~4 % of the carpet's points), by medium cell from a 4 KB table before
  // cubeBandTest's 512 KB one, which the frames between scans evict: ~1 in 6 remain.
  if (markers_only) maybe = mediumRangeTest(lookup, c, level, maybe);
  if (!maybe) return;
  const __m512i cube = cubeOf(c);
  const __mmask16 candidates =
      markers_only ? cubeBandTest(lookup, cube, level, maybe) : cubeClassTest(lookup, cube, wanted, maybe);
  if (!candidates) return;
  // The lookup proper in registers too (one scalar lookup per point was dearer).
  const __m512i label = labelsOf(lookup, c, cube, level, candidates);
  unsigned found =
      _mm512_mask_test_epi32_mask(candidates, _mm512_sllv_epi32(_mm512_set1_epi32(1), label), wanted);
  while (found) {
    hits.emplace_back(x + __builtin_ctz(found) * stride, y);
    found &= found - 1;
  }
}

// Lanes 16 * half .. 16 * half + 15 of 16-bit lanes, widened to 32 bits.
SV_AVX512 inline __m512i widenHalf(__m512i words, int half) {
  return _mm512_cvtepu16_epi32(half ? _mm512_extracti64x4_epi64(words, 1) : _mm512_castsi512_si256(words));
}

// One step of scanRowAvx512 on its own: the n (<= 16) points from label x on.
template <int Step>
SV_AVX512 inline void scanStepAvx512(const ClassLookup& lookup, const LabelRow& row,
                                     const RowAdjustment& adjusted, int y, int x, int n, int stride,
                                     ClassMask classes, const __m512i (&ranges)[8],
                                     std::vector<cv::Point>& hits) {
  const int span = Step * stride;
  const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const Colours c = pickColours<Step>(row, x, n, span, spanIndex(span));
  const __m512i lane_x =
      _mm512_add_epi32(_mm512_set1_epi32(x), _mm512_mullo_epi32(lanes, _mm512_set1_epi32(stride)));
  const __m512i level = adjustedLevels(c, laneAdjustment(adjusted, x, lane_x));
  // Most points (carpet) end here, tested in registers without touching the tables.
  const __mmask16 maybe =
      onlyMarkerClasses(classes) ? rangeTest(c, level, ranges, firstLanes(n)) : firstLanes(n);
  if (maybe) lookUpCandidates(lookup, c, level, maybe, x, y, stride, classes, hits);
}

// scanRow, as many points at a time as lie in 128 bytes of each channel's row (at most 16).
template <int Step>
SV_AVX512 void scanRowAvx512(const ClassLookup& lookup, const LabelRow& row, const RowAdjustment& adjusted,
                             int y, int x0, int x1, int stride, ClassMask classes,
                             const std::uint8_t* image_end, std::vector<cv::Point>& hits) {
  const int span = Step * stride;  // bytes from one point to the next
  constexpr int kPointBytes = Step == 3 ? 3 : 1;
  const int per_step = std::min(16, (128 - kPointBytes) / span + 1);
  const int points = (x1 - x0 + stride - 1) / stride;
  int done = 0;
  if (per_step >= 4) {
    const bool markers_only = onlyMarkerClasses(classes);
    __m512i ranges[8];
    for (int k = 0; k < 8; ++k) ranges[k] = _mm512_loadu_si512(lookup.coarse_marker_range + 64 * k);
    if (markers_only && gainsFitInt16(adjusted)) {
      const __m512i word_index = wordSpanIndex(span, 0);
      // Each lane's x less the pair's first: lanes 16..31 continue from per_step points on.
      const __m512i lane_x = _mm512_mullo_epi16(
          _mm512_set_epi16(per_step + 15, per_step + 14, per_step + 13, per_step + 12, per_step + 11,
                           per_step + 10, per_step + 9, per_step + 8, per_step + 7, per_step + 6,
                           per_step + 5, per_step + 4, per_step + 3, per_step + 2, per_step + 1, per_step, 15,
                           14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0),
          _mm512_set1_epi16(static_cast<short>(stride)));
      for (; done < points; done += 2 * per_step) {
        StepPair s;
        s.n[0] = std::min(per_step, points - done);
        s.n[1] = std::min(per_step, points - done - s.n[0]);
        s.x[0] = x0 + done * stride;
        s.x[1] = s.x[0] + per_step * stride;
        const Colours16 c = pickColourPairs<Step>(row, s, span, word_index, image_end);
        const __mmask32 live = firstLanes(s.n[0]) | static_cast<__mmask32>(firstLanes(s.n[1])) << 16;
        const __m512i level = adjustedLevelPairs(c, adjusted, s.x[0], lane_x);
        const __mmask32 maybe = rangeTestPairs(c, level, ranges, live);
        for (int h = 0; h < 2; ++h) {
          const auto half = static_cast<__mmask16>(maybe >> (16 * h));
          if (!half) continue;
          const Colours wide{widenHalf(c.b, h), widenHalf(c.g, h), widenHalf(c.r, h)};
          lookUpCandidates(lookup, wide, widenHalf(level, h), half, s.x[h], y, stride, classes, hits);
        }
      }
    }
    for (; done < points; done += per_step) {
      const int n = std::min(per_step, points - done);
      scanStepAvx512<Step>(lookup, row, adjusted, y, x0 + done * stride, n, stride, classes, ranges, hits);
    }
  }
  const int rest = x0 + done * stride;
  if (rest < x1) scanRow<Step>(lookup, row, adjusted, y, rest, x1, stride, classes, hits);
}

// classifyRowKeeping, 16 label pixels per step: colours picked as by the scan, the cube test
// (by V' band when only markers are kept), then labelsOf.
template <int Step>
SV_AVX512 void classifyRowAvx512(const ClassLookup& lookup, const LabelRow& row,
                                 const RowAdjustment& adjusted, int x0, int x1, ClassMask keep,
                                 std::uint8_t* out) {
  constexpr int span = Step;  // bytes from one label pixel to the next
  const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i index = spanIndex(span);
  const __m512i wanted = _mm512_set1_epi32(static_cast<int>(keep & 0xFFFF));
  const __m512i zero = _mm512_setzero_si512();
  const bool markers_only = onlyMarkerClasses(keep);
  for (int x = x0; x < x1; x += 16) {
    const int n = std::min(16, x1 - x);
    const __mmask16 live = firstLanes(n);
    const Colours c = pickColours<Step>(row, x, n, span, index);
    const __m512i cube = cubeOf(c);
    const __m512i level =
        adjustedLevels(c, laneAdjustment(adjusted, x, _mm512_add_epi32(_mm512_set1_epi32(x), lanes)));
    const __mmask16 may =
        markers_only ? cubeBandTest(lookup, cube, level, live) : cubeClassTest(lookup, cube, wanted, live);
    __m512i label = zero;
    if (may) {
      label = labelsOf(lookup, c, cube, level, may);
      const __mmask16 kept =
          _mm512_mask_test_epi32_mask(may, _mm512_sllv_epi32(_mm512_set1_epi32(1), label), wanted);
      label = _mm512_maskz_mov_epi32(kept, label);
    }
    _mm_mask_storeu_epi8(out + (x - x0), live, _mm512_cvtepi32_epi8(label));
  }
}
#pragma GCC diagnostic pop
#endif

constexpr ClassMask kAllClasses = (ClassMask(1) << kNumColorClasses) - 1;

// Asks for the image bytes of label pixels x0 .. x1 - 1 of label row y ahead of their use:
// the hardware prefetchers follow a row, but not the jump to the next one the loops make.
void prefetchLabelRow(const cv::Mat& image, PixelLayout layout, int y, int x0, int x1) {
  if (x0 >= x1) return;
  const int rows = isBayer(layout) ? 2 : 1, bytes_per_pixel = isBayer(layout) ? 2 : 3;
  for (int i = 0; i < rows; ++i) {
    const std::uint8_t* p = image.ptr<std::uint8_t>(rows * y + i);
    const std::uint8_t* end = p + static_cast<std::ptrdiff_t>(x1) * bytes_per_pixel;
    for (p += static_cast<std::ptrdiff_t>(x0) * bytes_per_pixel; p < end; p += 64) __builtin_prefetch(p);
    __builtin_prefetch(end - 1);
  }
}

RowAdjustment rowAdjustment(const cv::Mat& offsets, const cv::Mat& gains, int block_shift, int y) {
  return {offsets.ptr<std::int16_t>(y >> block_shift), gains.ptr<std::uint16_t>(y >> block_shift),
          block_shift, offsets.cols};
}

}  // namespace

void FrameClassifier::classify(const cv::Rect& rect, cv::Mat& out, ClassMask keep) const {
  checkRect(rect);
  out.create(rect.size(), CV_8UC1);
  if (!sharpen_terms_.empty()) {
    classifySharpened(rect, out, keep);
    return;
  }
  const ClassLookup& lookup = *classifier_.lookup_;
  const bool all = (keep & kAllClasses) == kAllClasses;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    std::uint8_t* labels = out.ptr<std::uint8_t>(y - rect.y);
    const LabelRow row = labelRow(image_, layout_, y);
    const RowAdjustment adjusted = rowAdjustment(offsets_, gains_, block_shift_, y);
    const int x0 = rect.x, x1 = rect.x + rect.width;
#ifdef SV_HAVE_AVX512_KERNELS
    if (detail::useAvx512Kernels()) {
      row.step == 3 ? classifyRowAvx512<3>(lookup, row, adjusted, x0, x1, keep, labels)
                    : classifyRowAvx512<2>(lookup, row, adjusted, x0, x1, keep, labels);
      continue;
    }
#endif
    if (all) {
      row.step == 3 ? classifyRow<3>(lookup, row, adjusted, x0, x1, labels)
                    : classifyRow<2>(lookup, row, adjusted, x0, x1, labels);
    } else {
      row.step == 3 ? classifyRowKeeping<3>(lookup, row, adjusted, x0, x1, keep, labels)
                    : classifyRowKeeping<2>(lookup, row, adjusted, x0, x1, keep, labels);
    }
  }
}

void FrameClassifier::classifySharpened(const cv::Rect& rect, cv::Mat& out, ClassMask keep) const {
  // V of the rect and a one-pixel ring around it (border replicated), read once.
  const int w = rect.width + 2;
  std::vector<int> v(static_cast<std::size_t>(w) * (rect.height + 2));
  for (int j = 0; j < rect.height + 2; ++j) {
    const LabelRow row = labelRow(image_, layout_, std::clamp(rect.y - 1 + j, 0, label_size_.height - 1));
    for (int i = 0; i < w; ++i)
      v[j * w + i] = valueAt(row, std::clamp(rect.x - 1 + i, 0, label_size_.width - 1));
  }
  const ClassLookup& lookup = *classifier_.lookup_;
  const std::int16_t* terms = sharpen_terms_.data() + kMaxLaplacian;
  for (int j = 0; j < rect.height; ++j) {
    const int y = rect.y + j;
    const LabelRow row = labelRow(image_, layout_, y);
    const RowAdjustment adjusted = rowAdjustment(offsets_, gains_, block_shift_, y);
    const int* above = &v[j * w + 1];
    const int* centre = above + w;
    const int* below = centre + w;
    std::uint8_t* labels = out.ptr<std::uint8_t>(j);
    for (int i = 0; i < rect.width; ++i) {
      const int x = rect.x + i;
      const int laplacian = above[i] + below[i] + centre[i - 1] + centre[i + 1] - 4 * centre[i];
      const int sharpened = clampV(centre[i] - terms[laplacian]);
      const std::uint8_t label =
          lookup.classAt(row.b[x * row.step], greenAt(row, x), row.r[x * row.step], adjusted(x, sharpened));
      labels[i] = keep & (ClassMask(1) << label) ? label : 0;
    }
  }
}

void FrameClassifier::scanGrid(const cv::Rect& rect, int stride, ClassMask classes,
                               std::vector<cv::Point>& hits) const {
  checkRect(rect);
  if (stride < 1) throw std::invalid_argument("FrameClassifier::scanGrid: stride must be >= 1");
  const int x0 = (rect.x + stride - 1) / stride * stride, x1 = rect.x + rect.width;
  for (int y = (rect.y + stride - 1) / stride * stride; y < rect.y + rect.height; y += stride) {
    scanRowPoints(y, x0, x1, stride, classes, hits);
  }
}

void FrameClassifier::scanPoints(int y, int x_begin, int x_end, int step, ClassMask classes,
                                 std::vector<cv::Point>& hits) const {
  if (step < 1) throw std::invalid_argument("FrameClassifier::scanPoints: step must be >= 1");
  if (x_begin >= x_end) return;
  checkRect(cv::Rect(x_begin, y, x_end - x_begin, 1));
  scanRowPoints(y, x_begin, x_end, step, classes, hits);
}

void FrameClassifier::scanRowPoints(int y, int x0, int x1, int step, ClassMask classes,
                                    std::vector<cv::Point>& hits) const {
  const ClassLookup& lookup = *classifier_.lookup_;
  const LabelRow row = labelRow(image_, layout_, y);
  if (!sharpen_terms_.empty()) {
    for (int x = x0; x < x1; x += step) {
      const int b = row.b[x * row.step], g = greenAt(row, x), r = row.r[x * row.step];
      if (!lookup.mayBeIn(b, g, r, classes)) continue;
      const int label = lookup.classAt(b, g, r, adjustedVAt(x, y, sharpenedV(x, y)));
      if (classes & (ClassMask(1) << label)) hits.emplace_back(x, y);
    }
    return;
  }
  const RowAdjustment adjusted = rowAdjustment(offsets_, gains_, block_shift_, y);
  // The next row of a grid (scanGrid's and the region extractor's rows step as their points).
  if (y + step < label_size_.height) prefetchLabelRow(image_, layout_, y + step, x0, x1);
#ifdef SV_HAVE_AVX512_KERNELS
  if (detail::useAvx512Kernels()) {
    row.step == 3 ? scanRowAvx512<3>(lookup, row, adjusted, y, x0, x1, step, classes, image_.dataend, hits)
                  : scanRowAvx512<2>(lookup, row, adjusted, y, x0, x1, step, classes, image_.dataend, hits);
    return;
  }
#endif
  if (row.step == 3) {
    scanRow<3>(lookup, row, adjusted, y, x0, x1, step, classes, hits);
  } else {
    scanRow<2>(lookup, row, adjusted, y, x0, x1, step, classes, hits);
  }
}

}  // namespace soccer_vision
