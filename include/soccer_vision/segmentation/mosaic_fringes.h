// Colour fringes of a Bayer mosaic's quads. A quad reads R, G and B at sites a pixel
// apart, so a quad across a sharp edge — a white line on the carpet — has the colour of
// neither side: R from the line and B from the carpet reads yellow, the other way round
// cyan. Along every field line this gives one-quad-thin regions that a generalised table
// takes for yellow and sky-blue markers (a clean 1280x1024 frame: about 120 per frame,
// enough to reach the per-class cap and push small markers out). Such a quad's two green
// sites, on opposite sides of the edge, disagree; inside a marker they agree up to noise.
// A region whose quads' greens mostly disagree is a fringe, not a marker.
#pragma once

#include <cstdint>

#include "soccer_vision/segmentation/pixel_classifier.h"
#include "soccer_vision/segmentation/run_length_components.h"

namespace soccer_vision {

// Whether a quad's greens agree: |G1 - G2| <= 8 + max(G1, G2) / 8. Sensor noise and carpet
// texture spread |G1 - G2| on a noisy held-out mosaic (rand_bayer) to p90 15 at mid grey
// and 21 at G 120-180; the edge of a white line on green is 60-120 apart.
inline bool greensAgree(int g1, int g2) {
  const int hi = g1 > g2 ? g1 : g2, d = g1 > g2 ? g1 - g2 : g2 - g1;
  return 8 * d <= 64 + hi;
}

// The quads of the runs [begin, end) (label pixels relative to `origin`) of a Bayer frame
// whose greens agree.
std::uint32_t quadsWithAgreeingGreens(const FrameClassifier& frame, const PixelRun* begin,
                                      const PixelRun* end, cv::Point origin);

}  // namespace soccer_vision
