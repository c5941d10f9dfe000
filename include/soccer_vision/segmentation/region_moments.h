// The moments of a region (centroid, second central moments, orientation): binary, from the
// closed-form sums of its runs, or coverage-weighted, from the colours of its edge pixels
// so that anti-aliased shapes give their true sub-pixel centroid.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/segmentation/pixel_classifier.h"
#include "soccer_vision/segmentation/run_length_components.h"

namespace soccer_vision {

struct Region;

// The principal standard deviations (major, minor) [px] of central second moments [px²]:
// a uniform ellipse's semi-axes are twice them.
struct PrincipalDeviations {
  double major = 0, minor = 0;
  double elongation() const { return minor > 0 ? major / minor : HUGE_VAL; }
};
PrincipalDeviations principalDeviations(double mu20, double mu11, double mu02);
// The major axis' angle [rad] of central second moments: 0.5 atan2(2 mu11, mu20 - mu02).
double majorAxisAngle(double mu20, double mu11, double mu02);

// A region taken for a band of even width along a curve (a line, its colour fringe, a
// cable): a band of length L varies about its centroid by at most L^2 / 12 (a straight one:
// exactly), so `length` = sqrt(12 (mu20 + mu02)) is L or less and `width` = area / length is
// the band's width or more. Exact for a long straight band; a w x h rectangle gives its
// diagonal and w h / diagonal, a disc 1.22 and 0.64 of its diameter. Both 0 without moments.
struct BandShape {
  double length = 0, width = 0;  // px
};
BandShape bandShape(const Region& r);

// A region's moment ellipse about its centroid, along its major axis: semi-axes a and b
// twice its principal standard deviations (a uniform ellipse's own outline) grown by `margin`.
struct MomentEllipse {
  double cx = 0, cy = 0, angle = 0;
  PrincipalDeviations sd;
  double a = 0, b = 0;
};
MomentEllipse momentEllipse(const Region& r, double margin);

// Binary moments of a component whose sums are relative to `origin` (label pixels).
void writeBinaryMoments(const ComponentStats& component, cv::Point origin, Region& r);

// Reusable buffers of coverageMoments (one per thread).
struct CoverageScratch {
  // Bit rows (bit x + 2, 64 px a word) over the region's bbox grown by its 2-pixel ring
  // (and 2 more rows each side): membership, membership dilated along rows.
  std::vector<std::uint64_t> member, near_in_row;
  // The samples in raster order, in runs of one kind (ring, region) along a row.
  struct Segment {
    int x, y, length;  // relative to the bbox
  };
  std::vector<Segment> segments;
  std::vector<std::int32_t> colors;  // columns: B, G, R of every sample
  std::vector<double> ring_colors;   // columns: B, G, R of the ring's samples
  std::vector<double> alphas;        // coverage per sample
};

// Coverage-weighted moments of the region made of the runs [begin, end) (coordinates
// relative to `origin`; r.bbox: their bounding box in label pixels) written to r; `image`:
// the label image's rectangle. The paper weights its moments by V(i, j) (eq. 5-6); here
// each pixel is weighted by its estimated coverage α = clamp((p - bg)·(c - bg) / |c - bg|²,
// 0, 1), c the mean colour of the interior (pixels with all 4-neighbours in the region; all
// region pixels for tiny regions), bg the mean colour of a 2-pixel ring around the region,
// then once more weighted by 1 - α, so that the partly covered ring pixels do not pull it
// towards c. A pixel whose colour lies far from the line between bg and c (another
// marker's, within the ring) counts in neither. On Bayer quads each of a quad's four
// sensor sites gives the coverage of its own channel at its own position, and only the
// ring's quads touching the region count (region_moments.cpp). Returns false (r's moments
// untouched) when the colours give no usable contrast: binary moments then.
bool coverageMoments(const FrameClassifier& frame, const PixelRun* begin, const PixelRun* end,
                     cv::Point origin, const cv::Rect& image, CoverageScratch& scratch, Region& r);

}  // namespace soccer_vision
