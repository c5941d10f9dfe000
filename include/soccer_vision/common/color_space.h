// Exact conversions of one 8-bit BGR pixel to the two colour spaces of the paper's colour
// table (§III-A): HSV, whose cells the table is indexed by, and CIE L*a*b*, in which the
// sample pixels of a class are filtered.
#pragma once

#include <array>
#include <cstdint>

namespace soccer_vision {

// h: degrees in [0, 360), 0 for greys (max == min).
// s: (max - min) / max in [0, 1], 0 for black.
// v: max(b, g, r) in 8-bit units 0..255, so that the paper's v' = v + k·Δv stays in
//    pixel units.
// Same numbers as OpenCV's float cvtColor(COLOR_BGR2HSV_FULL) on inputs scaled to [0, 1]
// (with v scaled back by 255).
struct Hsv {
  double h = 0, s = 0, v = 0;
};

// CIE L*a*b* of an sRGB (D65) pixel: L in [0, 100], a and b roughly in [-128, 127].
// Same formulas and constants as OpenCV's float cvtColor(COLOR_BGR2Lab) on inputs scaled
// to [0, 1], but exact: OpenCV 4 interpolates that conversion in a lookup table (up to
// ~0.5 ΔE off); its COLOR_LBGR2Lab on exactly linearised input agrees within 0.05 ΔE.
struct Lab {
  double l = 0, a = 0, b = 0;
};

Hsv bgrToHsv(std::uint8_t b, std::uint8_t g, std::uint8_t r);
Lab bgrToLab(std::uint8_t b, std::uint8_t g, std::uint8_t r);
// The inverse of bgrToHsv, rounded to 8 bits: the pixel of hue h (degrees, any value:
// wrapped), saturation s (clamped to [0, 1]) and value v (clamped to [0, 255]).
std::array<std::uint8_t, 3> hsvToBgr(const Hsv& hsv);

// CIE76 colour difference: Euclidean distance in L*a*b*.
double labDistance(const Lab& x, const Lab& y);

// Signed hue difference a - b wrapped to (-180, 180] degrees.
double hueDifference(double a, double b);
// Circular hue distance |a - b| in [0, 180] degrees: 355° and 5° are 10° apart.
double hueDistance(double a, double b);

}  // namespace soccer_vision
