// Regions of the paper (§III, Fig. 3): per colour class, morphological open + close,
// connected components, area filter, and first/second-order moments per region — found
// without classifying the whole frame.
//
// Why that is exact: an opening with a k x k square keeps only pixels that belong to some
// k x k square of the class, and every k x k square contains exactly one point of the
// stride-k grid. So every region that survives open + close contains a grid point of its
// class: a scan of the grid (1/k² of the pixels) finds every region, and full
// classification is then needed only in tiles around the hits, grown until no region
// touches the border of what was classified. The result equals morphology + connected
// components on the fully classified frame (tested against OpenCV on random label images).
// With morphology off (kernel 0 or 1) the stride is 1 (every pixel), or the checkerboard
// when regions must hold two adjacent pixels (require_pair: the same argument for dominoes).
// A grid coarser than the kernel (RegionParams::scan_stride, the default with the 2x2
// opening) finds the regions that hold one of its points: exactly those, the classification
// flooding out from the tiles around their hits along the classes' pixels.
//
// Search windows restrict the scan and the classification to given rectangles; regions
// crossing a window border are followed out of it (grown like tiles), so they are never
// split.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/color_class.h"
#include "soccer_vision/segmentation/pixel_classifier.h"

namespace soccer_vision {

struct Region {
  ColorClass color = ColorClass::None;
  std::uint32_t area = 0;               // pixels of the (opened, closed) binary region
  double cx = 0, cy = 0;                // sub-pixel centroid (label coordinates; see moments below)
  double mu20 = 0, mu11 = 0, mu02 = 0;  // central second moments / weight, px²
  double orientation = 0;               // major axis angle, 0.5 * atan2(2 mu11, mu20 - mu02), rad
  cv::Rect bbox;                        // of the binary region
};

struct RegionParams {
  // Open + close with a k x k square; 0 = off. 2, not 3: in a wide-angle lens' corner a
  // 30 mm team tag is 4-5 px wide, and a few of its pixels read as another class; the 3x3
  // opening cut it into fragments too small for a tag (held-out seeds 9031/9032
  // rand_wide_angle: one robot measured in 80-90 % of its frames). 2x2 keeps such a tag and
  // still removes single pixels and one-pixel lines (a ball's rim read yellow, which makes
  // a ball look like it lies on a team-coloured region; with no opening at all it did).
  int morph_kernel = 2;
  // [px] The scan's grid with an opening (morph_kernel >= 2): max(morph_kernel, scan_stride).
  // A region is found where it holds a grid point; every region holding a k x k square holds
  // a point of the stride-k grid, so with scan_stride <= morph_kernel the result is exactly
  // the opening's components. 3 with the 2x2 opening: the stride-3 grid reads 0.45x the
  // points of the stride-2 one (full frame 1.55x faster at 1280x1024), and what it may miss
  // is thinner than 3 px across (no 3x3 square fits): a line's fragment or a rim, never a
  // marker's body. 0 = the kernel (exact).
  int scan_stride = 3;
  int min_area = 5;                // px, smaller regions are dropped
  int max_area = 20000;            // px, larger regions are dropped
  int max_regions_per_class = 64;  // the cap: more are dropped and counted in cap_hits
  int tile_size = 16;              // label px of the classification tiles (16 beat 8 and 32 in the benchmark)
  // With morphology off (morph_kernel <= 1): only regions holding two 4-adjacent pixels
  // of their class (a domino) are kept; single pixels and diagonal chains of them are
  // dropped. Every domino covers exactly one point of the checkerboard grid (x + y even),
  // so the scan reads half the pixels and still finds every such region, with all its
  // pixels (unlike an opening, which would take the partly covered edge quads of a
  // 3-quad-wide Bayer tag). Ignored with morphology on.
  bool require_pair = false;
  ClassMask classes = markerClassMask();
  // Sub-pixel moments: edge pixels weighted by their estimated coverage (their colour
  // between the region's interior colour and the surrounding colour), so that anti-aliased
  // shapes give their true centroid; false = plain binary moments.
  bool coverage_weighted_moments = true;
  // Bayer quads only: regions in which fewer than this share of the quads have agreeing
  // greens are colour fringes along an edge (mosaic_fringes.h), dropped before the cap and
  // counted in RegionStatistics::fringes. On clean rendered frames the markers had >= 40 %
  // (median 80-90 %), the fringes 0 % (95th percentile 2-14 %). 0 = off.
  double min_agreeing_green_share = 0.25;
};

struct RegionStatistics {
  std::array<std::uint32_t, kNumColorClasses> cap_hits{};  // regions dropped by the cap
  std::array<std::uint32_t, kNumColorClasses> fringes{};   // Bayer colour fringes dropped
  std::uint32_t grid_points = 0;                           // pixels classified by the grid scan
  std::uint32_t classified_pixels = 0;                     // pixels classified in tiles
  double classify_ms = 0, morphology_ms = 0, regions_ms = 0;
};

struct RegionScratch;  // reusable buffers of the implementation

// The stride of the scan's grid: with an opening (morph_kernel >= 2) max(morph_kernel,
// scan_stride), without one 1 (require_pair scans the checkerboard instead).
int scanGridStride(const RegionParams& p);

class RegionExtractor {
 public:
  explicit RegionExtractor(const RegionParams& params = {});
  const RegionParams& params() const { return params_; }

  // Regions of the whole frame (windows empty) or of the union of the windows (label
  // coordinates). Reuses internal buffers, which copies of an extractor share: one
  // extractor per thread.
  void extract(const FrameClassifier& frame, const std::vector<cv::Rect>& windows,
               std::vector<Region>& regions, RegionStatistics& stats);

 private:
  RegionParams params_;
  std::shared_ptr<RegionScratch> scratch_;
};

}  // namespace soccer_vision
