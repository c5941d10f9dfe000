#include "soccer_vision/segmentation/region_moments.h"

#include <algorithm>
#include <array>

#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {
namespace {

constexpr int kRing = 2;  // px around a region sampled for coverage
// A sample whose colour lies farther than this share of the contrast from the line between
// background and interior colour is foreign (weightedMoments), its coverage kForeign.
constexpr double kMaxOffLine = 0.5;
constexpr double kForeign = -1.0;
constexpr int kWordBits = 64;

// A region's bits: rows y in [-2 kRing, height + 2 kRing) of its bbox (the ring's rows
// with their neighbours' within kRing, zero beyond the bbox's), bit x + kRing of a row for
// x in [-kRing, width + kRing), `words` words a row.
struct BitRows {
  int width, words, rows;
  explicit BitRows(const cv::Rect& bbox)
      : width(bbox.width),
        words((bbox.width + 2 * kRing + kWordBits - 1) / kWordBits),
        rows(bbox.height + 4 * kRing) {}
  std::size_t size() const { return static_cast<std::size_t>(words) * rows; }
  std::size_t at(int y) const { return static_cast<std::size_t>(y + 2 * kRing) * words; }
  // Bit (x, y) of `bits`; false outside the rows and columns held.
  bool test(const std::uint64_t* bits, int x, int y) const {
    const int bit = x + kRing;
    if (bit < 0 || x >= width + kRing || y < -2 * kRing || y >= rows - 2 * kRing) return false;
    return (bits[at(y) + static_cast<std::size_t>(bit / kWordBits)] >> (bit % kWordBits) & 1) != 0;
  }
};

// Word i of `row` moved by k bits towards higher x (k < 0: lower x), zeros shifted in.
inline std::uint64_t shifted(const std::uint64_t* row, int words, int i, int k) {
  if (k > 0) return row[i] << k | (i > 0 ? row[i - 1] >> (kWordBits - k) : 0);
  return row[i] >> -k | (i + 1 < words ? row[i + 1] << (kWordBits + k) : 0);
}

// Bits [lo, hi) of a word (0 <= lo < hi <= 64).
inline std::uint64_t bitRange(int lo, int hi) {
  return (hi == kWordBits ? ~std::uint64_t{0} : (std::uint64_t{1} << hi) - 1) &
         ~((std::uint64_t{1} << lo) - 1);
}

// Bits [begin, end) (begin < end) of a row.
inline void setBits(std::uint64_t* row, int begin, int end) {
  for (int i = begin / kWordBits; i <= (end - 1) / kWordBits; ++i) {
    row[i] |= bitRange(std::max(begin - i * kWordBits, 0), std::min(end - i * kWordBits, kWordBits));
  }
}

// Moments from weighted sums of x, y (relative to `origin`), x², xy, y².
struct MomentSums {
  double w = 0, x = 0, y = 0, xx = 0, xy = 0, yy = 0;
  MomentSums() = default;
  explicit MomentSums(const ComponentStats& c)
      : w(c.area),
        x(double(c.sum_x)),
        y(double(c.sum_y)),
        xx(double(c.sum_xx)),
        xy(double(c.sum_xy)),
        yy(double(c.sum_yy)) {}
  void add(double px, double py, double weight) {
    w += weight;
    x += weight * px;
    y += weight * py;
    xx += weight * px * px;
    xy += weight * px * py;
    yy += weight * py * py;
  }
  void writeTo(Region& r, cv::Point origin) const {
    const double mx = x / w, my = y / w;
    r.cx = origin.x + mx;
    r.cy = origin.y + my;
    r.mu20 = xx / w - mx * mx;
    r.mu11 = xy / w - mx * my;
    r.mu02 = yy / w - my * my;
    r.orientation = majorAxisAngle(r.mu20, r.mu11, r.mu02);
  }
};

// The colour (B, G, R) of the label pixel `at` (byte offset) of `row`.
inline std::array<int, 3> colorAt(const LabelRow& row, std::ptrdiff_t at) {
  return {row.b[at], (row.g1[at] + row.g2[at] + 1) >> 1, row.r[at]};
}

// The colours of the `length` ring pixels of `row` from `x`, written to the columns `out`
// and, as doubles, `ring`, and added to `sum`.
inline void copyRing(const LabelRow& row, int x, int length, std::array<std::int32_t*, 3> out,
                     std::array<double*, 3> ring, std::array<int, 3>& sum) {
  for (int k = 0; k < length; ++k) {
    const std::array<int, 3> color = colorAt(row, static_cast<std::ptrdiff_t>(x + k) * row.step);
    for (int c = 0; c < 3; ++c) {
      out[c][k] = color[c];
      ring[c][k] = color[c];
      sum[c] += color[c];
    }
  }
}

// The colours of the `length` region pixels of `row` from `x`, written to the columns
// `out` and added to `sum`, and to `interior_sum` where bit k of `interior` is set.
inline void copyRegion(const LabelRow& row, int x, int length, std::uint64_t interior,
                       std::array<std::int32_t*, 3> out, std::array<int, 3>& sum,
                       std::array<int, 3>& interior_sum) {
  for (int k = 0; k < length; ++k) {
    const std::array<int, 3> color = colorAt(row, static_cast<std::ptrdiff_t>(x + k) * row.step);
    const int mask = -static_cast<int>(interior >> k & 1);
    for (int c = 0; c < 3; ++c) {
      out[c][k] = color[c];
      sum[c] += color[c];
      interior_sum[c] += color[c] & mask;
    }
  }
}

// Bayer quads: a quad's colour comes from four sensor sites a pixel apart, and at a
// region's edge they see different coverages, so a quad's coverage placed at its centre
// pulls the centroid towards the site of the channel with the most contrast (markers of
// rendered RGGB frames: median 0.41 px off, the small id markers' heading bias; 0.07 px
// with this). Here each site gives the coverage of its own channel at its own position,
// weighted by that channel's share of the squared contrast (the two G sites half each): on
// a uniformly covered quad the projection of the quad colour, at an edge the coverage where
// it was seen. Quads whose colour is foreign (`quad_alphas`, kForeign) are left out.
void addSiteCoverages(const FrameClassifier& frame, const cv::Rect& bbox, const std::uint64_t* member,
                      const CoverageScratch::Segment* segments, int segment_n, const double* quad_alphas,
                      const cv::Vec3d& background, const cv::Vec3d& contrast, MomentSums& sums) {
  // Quads hold no opening (require_pair keeps every quad of the class), so a partly covered
  // quad touches the region: the ring's outer quads, 3-4 px out, are left to the
  // background. They would add what lies beyond: the carpet, a darker green, around the
  // SSL pattern's green dots at the robot's rim (0.44 px median centroid error with them).
  const BitRows bits(bbox);
  auto touchesRegion = [&](int x, int y) {  // itself or one of its 8 neighbours a member
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (bits.test(member, x + dx, y + dy)) return true;
      }
    }
    return false;
  };
  const double contrast2 = contrast.dot(contrast);
  struct Site {
    double dx, dy;  // label pixels from the quad's centre: image pixels / 2
    double background, inverse_contrast, weight;
  };
  const QuadSites where = quadSites(frame.layout());
  auto site = [&](cv::Point at, int channel, double share) {
    const double k = contrast[channel];
    return Site{(at.x - 0.5) / 2, (at.y - 0.5) / 2, background[channel], k != 0 ? 1.0 / k : 0.0,
                share * k * k / contrast2};
  };
  // LabelRow's order: b, g1, g2, r; the colour columns' order: B, G, R.
  const std::array<Site, 4> sites = {site(where.b, 0, 1.0), site(where.g1, 1, 0.5), site(where.g2, 1, 0.5),
                                     site(where.r, 2, 1.0)};
  for (int k = 0; k < segment_n; ++k) {
    const CoverageScratch::Segment& segment = segments[k];
    const LabelRow row = frame.row(bbox.y + segment.y);
    for (int j = 0; j < segment.length; ++j, ++quad_alphas) {
      if (*quad_alphas == kForeign) continue;  // the quad's colour is another marker's
      if (!touchesRegion(segment.x + j, segment.y)) continue;
      const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(bbox.x + segment.x + j) * row.step;
      const std::array<int, 4> values = {row.b[at], row.g1[at], row.g2[at], row.r[at]};
      for (int i = 0; i < 4; ++i) {
        const Site& s = sites[i];
        const double alpha = std::min(std::max((values[i] - s.background) * s.inverse_contrast, 0.0), 1.0);
        if (alpha > 0) sums.add(segment.x + j + s.dx, segment.y + s.dy, s.weight * alpha);
      }
    }
  }
}

// The coverage weighting of the header. The ring around the region is kRing = 2 px wide,
// not 1: the opening cuts the corners of a rectangle, and partly covered pixels there lie
// two pixels from the region (a 16x6 px tag: 0.10 px / 0.57 deg error with a one-pixel
// ring, 0.03 px / 0.24 deg with two). `s.member` marks the region (BitRows of bbox).
bool weightedMoments(const FrameClassifier& frame, const cv::Rect& bbox, const cv::Rect& image,
                     CoverageScratch& s, Region& r) {
  const BitRows bits(bbox);
  const int words = bits.words;
  // Ring: within kRing px (chessboard) of the region, not in it; separable dilation of
  // whole words, along rows here, across rows while sampling (the grown bbox holds the
  // region's dilation: no bounds).
  s.near_in_row.assign(bits.size(), 0);
  for (int y = 0; y < bbox.height; ++y) {  // members lie in the bbox's rows only
    const std::uint64_t* in = s.member.data() + bits.at(y);
    std::uint64_t* out = s.near_in_row.data() + bits.at(y);
    for (int i = 0; i < words; ++i) {
      std::uint64_t v = in[i];
      for (int d = 1; d <= kRing; ++d) v |= shifted(in, words, i, d) | shifted(in, words, i, -d);
      out[i] = v;
    }
  }
  // Samples in raster order (the sums below depend on the order in their last bits), in
  // segments of one kind (ring, region): their positions, and their colours as columns
  // (B, G, R of every sample, then of the ring's). The colour sums are of integers: exact.
  const int x_begin = std::max(-kRing, -bbox.x), x_end = std::min(bbox.width + kRing, image.width - bbox.x);
  const int y_begin = std::max(-kRing, -bbox.y), y_end = std::min(bbox.height + kRing, image.height - bbox.y);
  const std::size_t capacity = static_cast<std::size_t>(x_end - x_begin) * (y_end - y_begin);
  if (s.alphas.size() < capacity) {
    s.segments.resize(capacity);
    s.colors.resize(3 * capacity);
    s.ring_colors.resize(3 * capacity);
    s.alphas.resize(capacity);
  }
  std::int32_t* const colors = s.colors.data();
  const std::array<std::int32_t*, 3> all = {colors, colors + capacity, colors + 2 * capacity};
  double* const ring_colors = s.ring_colors.data();
  const std::array<double*, 3> ring = {ring_colors, ring_colors + capacity, ring_colors + 2 * capacity};
  CoverageScratch::Segment* const segments = s.segments.data();
  std::array<int, 3> ring_sum{}, region_sum{}, interior_sum{};
  int n = 0, ring_n = 0, region_n = 0, interior_n = 0, segment_n = 0;
  for (int y = y_begin; y < y_end; ++y) {
    const LabelRow row = frame.row(bbox.y + y);
    const std::uint64_t* near_in_row = s.near_in_row.data() + bits.at(y);
    const std::uint64_t* member = s.member.data() + bits.at(y);
    for (int i = 0; i < words; ++i) {
      // The image's columns of this word: bits x_begin + kRing .. x_end + kRing - 1.
      const int lo = std::max(x_begin + kRing - i * kWordBits, 0),
                hi = std::min(x_end + kRing - i * kWordBits, kWordBits);
      if (lo >= hi) continue;
      std::uint64_t todo = 0;
      for (int d = -kRing; d <= kRing; ++d) todo |= near_in_row[i + static_cast<std::ptrdiff_t>(d) * words];
      todo &= bitRange(lo, hi);
      const std::uint64_t ring_bits = todo & ~member[i];
      // Interior: the member and its 4 neighbours.
      const std::uint64_t interior_bits = member[i] & shifted(member, words, i, 1) &
                                          shifted(member, words, i, -1) &
                                          member[static_cast<std::ptrdiff_t>(i) - words] & member[i + words];
      interior_n += __builtin_popcountll(interior_bits);
      while (todo != 0) {
        const int first = __builtin_ctzll(todo);
        const bool in_ring = ring_bits >> first & 1;
        const std::uint64_t rest =
            ~((in_ring ? ring_bits : member[i]) >> first);  // its lowest set bit ends the segment
        const int length = rest == 0 ? kWordBits : __builtin_ctzll(rest);
        const int x = i * kWordBits + first - kRing;
        segments[segment_n++] = {x, y, length};
        const std::array<std::int32_t*, 3> out = {all[0] + n, all[1] + n, all[2] + n};
        if (in_ring) {
          copyRing(row, bbox.x + x, length, out, {ring[0] + ring_n, ring[1] + ring_n, ring[2] + ring_n},
                   ring_sum);
          ring_n += length;
        } else {
          copyRegion(row, bbox.x + x, length, interior_bits >> first, out, region_sum, interior_sum);
          region_n += length;
        }
        n += length;
        const int end = first + length;
        todo = end == kWordBits ? 0 : todo >> end << end;
      }
    }
  }
  auto vec = [](const std::array<int, 3>& v) { return cv::Vec3d(v[0], v[1], v[2]); };
  const cv::Vec3d inner = interior_n > 0 ? vec(interior_sum) / interior_n : vec(region_sum) / region_n;
  // Pass 1: the plain mean of the ring; pass 2: weighted by 1 - coverage.
  if (ring_n == 0) return false;
  cv::Vec3d background = vec(ring_sum) / static_cast<double>(ring_n);
  cv::Vec3d contrast = inner - background;
  double contrast2 = contrast.dot(contrast);
  if (contrast2 < 1.0) return false;  // less than one grey level apart: coverage is noise
  // Coverages of `count` colours (columns) into alphas (independent divisions: a loop the
  // compiler vectorises).
  double* const alphas = s.alphas.data();
  // A colour far from the line between background and interior is a mixture with neither:
  // another marker within the ring (the SSL pattern's dots lie 2-3 px apart at 1280 px, the
  // Bayer quads' ring is 4 px wide). It gets kForeign: no weight in the region, none in the
  // background.
  auto coverages = [&](const auto& color, int count) {
    const double b0 = background[0], b1 = background[1], b2 = background[2];
    const double k0 = contrast[0], k1 = contrast[1], k2 = contrast[2], k = contrast2;
    const double off_line2 = kMaxOffLine * kMaxOffLine * k;
    const auto *b = color[0], *g = color[1], *rr = color[2];
    for (int j = 0; j < count; ++j) {
      const double d0 = b[j] - b0, d1 = g[j] - b1, d2 = rr[j] - b2;
      const double projection = d0 * k0 + d1 * k1 + d2 * k2;              // cv::Vec's order
      const double alpha = std::min(std::max(projection / k, 0.0), 1.0);  // = std::clamp, without branches
      const double off_line = d0 * d0 + d1 * d1 + d2 * d2 - projection * projection / k;
      alphas[j] = off_line > off_line2 ? kForeign : alpha;
    }
  };
  {
    coverages(ring, ring_n);
    cv::Vec3d sum(0, 0, 0);
    double weight = 0;
    for (int j = 0; j < ring_n; ++j) {
      const double w = alphas[j] == kForeign ? 0.0 : 1.0 - alphas[j];
      for (int c = 0; c < 3; ++c) sum[c] += w * ring[c][j];
      weight += w;
    }
    if (weight <= 0) return false;
    background = sum / weight;
    contrast = inner - background;
    contrast2 = contrast.dot(contrast);
    if (contrast2 < 1.0) return false;
  }
  MomentSums sums;
  coverages(all, n);
  if (isBayer(frame.layout())) {
    addSiteCoverages(frame, bbox, s.member.data(), segments, segment_n, alphas, background, contrast, sums);
  } else {
    const double* alpha = alphas;
    for (int k = 0; k < segment_n; ++k) {
      const CoverageScratch::Segment& segment = segments[k];
      const double py = segment.y;
      double px = segment.x;
      for (int j = 0; j < segment.length; ++j, px += 1) {
        if (alpha[j] > 0) sums.add(px, py, alpha[j]);
      }
      alpha += segment.length;
    }
  }
  if (sums.w <= 0) return false;
  sums.writeTo(r, bbox.tl());
  return true;
}

}  // namespace

PrincipalDeviations principalDeviations(double mu20, double mu11, double mu02) {
  const double half_trace = 0.5 * (mu20 + mu02);
  const double spread = std::sqrt(0.25 * (mu20 - mu02) * (mu20 - mu02) + mu11 * mu11);
  return {std::sqrt(std::max(0.0, half_trace + spread)), std::sqrt(std::max(0.0, half_trace - spread))};
}

double majorAxisAngle(double mu20, double mu11, double mu02) {
  return 0.5 * std::atan2(2 * mu11, mu20 - mu02);
}

BandShape bandShape(const Region& r) {
  const double spread = 12 * (r.mu20 + r.mu02);
  if (!(spread > 0)) return {};
  const double length = std::sqrt(spread);
  return {length, r.area / length};
}

MomentEllipse momentEllipse(const Region& r, double margin) {
  MomentEllipse e;
  e.cx = r.cx;
  e.cy = r.cy;
  e.angle = majorAxisAngle(r.mu20, r.mu11, r.mu02);
  e.sd = principalDeviations(r.mu20, r.mu11, r.mu02);
  e.a = 2 * e.sd.major + margin;
  e.b = 2 * e.sd.minor + margin;
  return e;
}

void writeBinaryMoments(const ComponentStats& component, cv::Point origin, Region& r) {
  MomentSums(component).writeTo(r, origin);
}

bool coverageMoments(const FrameClassifier& frame, const PixelRun* begin, const PixelRun* end,
                     cv::Point origin, const cv::Rect& image, CoverageScratch& s, Region& r) {
  const cv::Rect& bbox = r.bbox;
  const BitRows bits(bbox);
  s.member.assign(bits.size(), 0);
  for (const PixelRun* run = begin; run != end; ++run) {
    const int dx = origin.x - bbox.x + kRing;
    setBits(s.member.data() + bits.at(run->y + origin.y - bbox.y), run->x_begin + dx, run->x_end + dx);
  }
  return weightedMoments(frame, bbox, image, s, r);
}

}  // namespace soccer_vision
