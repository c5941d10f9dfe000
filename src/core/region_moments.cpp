#include "soccer_vision/region_moments.h"

#include <algorithm>
#include <array>

#include "soccer_vision/region_extractor.h"

namespace soccer_vision {
namespace {

constexpr int kRing = 2;         // px around a region sampled for coverage
constexpr int kPad = 2 * kRing;  // margin of the region's membership buffer: the ring's ring

// Moments from weighted sums of x, y (relative to `origin`), x², xy, y².
struct MomentSums {
  double w = 0, x = 0, y = 0, xx = 0, xy = 0, yy = 0;
  MomentSums() = default;
  explicit MomentSums(const ComponentStats& c)
      : w(c.area), x(double(c.sum_x)), y(double(c.sum_y)), xx(double(c.sum_xx)), xy(double(c.sum_xy)),
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
    r.orientation = 0.5 * std::atan2(2 * r.mu11, r.mu20 - r.mu02);
  }
};

// The coverage weighting of the header. The ring around the region is kRing = 2 px wide,
// not 1: the opening cuts the corners of a rectangle, and partly covered pixels there lie
// two pixels from the region (a 16x6 px tag: 0.10 px / 0.57 deg error with a one-pixel
// ring, 0.03 px / 0.24 deg with two). `s.inside` marks the region in its bbox grown by kPad.
bool weightedMoments(const FrameClassifier& frame, const cv::Rect& bbox, const cv::Rect& image, CoverageScratch& s,
                     Region& r) {
  const int stride = bbox.width + 2 * kPad;
  auto at = [&](int x, int y) { return static_cast<std::size_t>(y + kPad) * stride + (x + kPad); };
  // Ring: within kRing px (chessboard) of the region, not in it; separable dilation. The
  // kPad = 2 kRing margin is zero, so both passes read +-kRing around every pixel of the
  // bbox grown by kRing without bounds checks (straight loops the compiler vectorises).
  s.near.assign(s.inside.size(), 0);
  s.near_in_row.assign(s.inside.size(), 0);
  const std::uint8_t* inside = s.inside.data();
  for (int y = 0; y < bbox.height; ++y) {  // members lie in the bbox's rows only
    const std::uint8_t* in = inside + at(0, y);
    std::uint8_t* out = s.near_in_row.data() + at(0, y);
    for (int x = -kRing; x < bbox.width + kRing; ++x) {
      std::uint8_t v = 0;
      for (int d = -kRing; d <= kRing; ++d) v |= in[x + d];
      out[x] = v;
    }
  }
  for (int y = -kRing; y < bbox.height + kRing; ++y) {
    const std::uint8_t* in = s.near_in_row.data() + at(0, y);
    std::uint8_t* out = s.near.data() + at(0, y);
    for (int x = -kRing; x < bbox.width + kRing; ++x) {
      std::uint8_t v = 0;
      for (int d = -kRing; d <= kRing; ++d) v |= in[x + static_cast<std::ptrdiff_t>(d) * stride];
      out[x] = v;
    }
  }
  // Samples in raster order (the sums below depend on the order in their last bits). The
  // colour sums are of integers: exact, kept in integer registers, converted once.
  std::array<int, 3> interior_sum{}, region_sum{}, ring_sum{};
  int interior_n = 0, region_n = 0, ring_n = 0;
  s.samples.clear();
  const int x_begin = std::max(-kRing, -bbox.x), x_end = std::min(bbox.width + kRing, image.width - bbox.x);
  const int y_begin = std::max(-kRing, -bbox.y), y_end = std::min(bbox.height + kRing, image.height - bbox.y);
  for (int y = y_begin; y < y_end; ++y) {
    const LabelRow row = frame.row(bbox.y + y);
    const std::uint8_t* near = s.near.data() + at(0, y);
    const std::uint8_t* member = inside + at(0, y);
    for (int x = x_begin; x < x_end; ++x) {
      if (!near[x]) continue;
      const int i = (bbox.x + x) * row.step;
      const std::array<int, 3> color = {row.b[i], (row.g1[i] + row.g2[i] + 1) >> 1, row.r[i]};
      const bool in_region = member[x] != 0;
      s.samples.push_back({x, y, cv::Vec3d(color[0], color[1], color[2]), in_region});
      std::array<int, 3>& sum = in_region ? region_sum : ring_sum;
      for (int c = 0; c < 3; ++c) sum[c] += color[c];
      if (in_region) {
        ++region_n;
        if (member[x - 1] && member[x + 1] && member[x - stride] && member[x + stride]) {
          for (int c = 0; c < 3; ++c) interior_sum[c] += color[c];
          ++interior_n;
        }
      } else {
        ++ring_n;
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
  auto coverage = [&](const cv::Vec3d& color) {
    double projection = 0;  // (color - background) . contrast, summed in cv::Vec's order
    for (int c = 0; c < 3; ++c) projection += (color[c] - background[c]) * contrast[c];
    return std::min(std::max(projection / contrast2, 0.0), 1.0);  // = std::clamp, without branches
  };
  {
    cv::Vec3d sum(0, 0, 0);
    double weight = 0;
    for (const CoverageScratch::Sample& p : s.samples) {
      if (p.in_region) continue;
      const double w = 1.0 - coverage(p.color);
      for (int c = 0; c < 3; ++c) sum[c] += w * p.color[c];
      weight += w;
    }
    if (weight <= 0) return false;
    background = sum / weight;
    contrast = inner - background;
    contrast2 = contrast.dot(contrast);
    if (contrast2 < 1.0) return false;
  }
  // Coverage of every sample first (independent divisions, no branch waiting on them),
  // then the sums of the covered ones.
  s.alphas.resize(s.samples.size());
  for (std::size_t i = 0; i < s.samples.size(); ++i) s.alphas[i] = coverage(s.samples[i].color);
  MomentSums sums;
  for (std::size_t i = 0; i < s.samples.size(); ++i) {
    if (s.alphas[i] > 0) sums.add(s.samples[i].x, s.samples[i].y, s.alphas[i]);
  }
  if (sums.w <= 0) return false;
  sums.writeTo(r, bbox.tl());
  return true;
}

}  // namespace

void writeBinaryMoments(const ComponentStats& component, cv::Point origin, Region& r) {
  MomentSums(component).writeTo(r, origin);
}

bool coverageMoments(const FrameClassifier& frame, const PixelRun* begin, const PixelRun* end, cv::Point origin,
                     const cv::Rect& image, CoverageScratch& s, Region& r) {
  // Membership of the bbox grown by kPad (outside it: not in the region).
  const cv::Rect& bbox = r.bbox;
  const int stride = bbox.width + 2 * kPad;
  s.inside.assign(static_cast<std::size_t>(stride) * (bbox.height + 2 * kPad), 0);
  for (const PixelRun* run = begin; run != end; ++run) {
    const std::size_t at = static_cast<std::size_t>(run->y + origin.y - bbox.y + kPad) * stride + kPad - bbox.x + origin.x;
    std::fill(s.inside.begin() + static_cast<std::ptrdiff_t>(at + run->x_begin),
              s.inside.begin() + static_cast<std::ptrdiff_t>(at + run->x_end), 1);
  }
  return weightedMoments(frame, bbox, image, s, r);
}

}  // namespace soccer_vision
