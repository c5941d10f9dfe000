#include "soccer_vision/common/color_space.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace soccer_vision {
namespace {

// sRGB primaries -> XYZ and the D65 white point, with OpenCV's digits so that Lab values
// agree with cvtColor (the reference other tools and users compare with).
constexpr double kRgbToXyz[3][3] = {
    {0.412453, 0.357580, 0.180423}, {0.212671, 0.715160, 0.072169}, {0.019334, 0.119193, 0.950227}};
constexpr double kWhite[3] = {0.950456, 1.0, 1.088754};
// CIE's linear segment near black (OpenCV's constants).
constexpr double kLabEpsilon = 0.008856;
constexpr double kLabKappa = 903.3;

// Linear light of an 8-bit sRGB value: exact IEC 61966-2-1 transfer curve, tabulated
// because only 256 inputs exist.
const std::array<double, 256>& srgbToLinear() {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[i] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    }
    return t;
  }();
  return table;
}

double labF(double t) { return t > kLabEpsilon ? std::cbrt(t) : 7.787 * t + 16.0 / 116.0; }

}  // namespace

Hsv bgrToHsv(std::uint8_t b, std::uint8_t g, std::uint8_t r) {
  const int max = std::max({b, g, r});
  const int min = std::min({b, g, r});
  const int range = max - min;
  Hsv hsv;
  hsv.v = max;
  if (max == 0 || range == 0) return hsv;  // black or grey: no saturation, hue 0
  hsv.s = static_cast<double>(range) / max;
  double h;
  if (max == r) {
    h = 60.0 * (g - b) / range;
  } else if (max == g) {
    h = 120.0 + 60.0 * (b - r) / range;
  } else {
    h = 240.0 + 60.0 * (r - g) / range;
  }
  hsv.h = h < 0 ? h + 360.0 : h;  // smallest negative h is -60/255 deg: never wraps to 360
  return hsv;
}

std::array<std::uint8_t, 3> hsvToBgr(const Hsv& hsv) {
  double h = std::fmod(hsv.h, 360.0);
  if (h < 0) h += 360.0;
  const double v = std::clamp(hsv.v, 0.0, 255.0), s = std::clamp(hsv.s, 0.0, 1.0);
  const double max = v, min = v * (1.0 - s), range = max - min;
  // bgrToHsv's three sectors, each of 120 degrees around the channel that is the maximum.
  double r, g, b;
  if (h < 60.0 || h >= 300.0) {  // max == r: h = 60 (g - b) / range
    const double d = (h >= 300.0 ? h - 360.0 : h) / 60.0 * range;
    r = max;
    g = d >= 0 ? min + d : min;
    b = d >= 0 ? min : min - d;
  } else if (h < 180.0) {  // max == g: h = 120 + 60 (b - r) / range
    const double d = (h - 120.0) / 60.0 * range;
    g = max;
    b = d >= 0 ? min + d : min;
    r = d >= 0 ? min : min - d;
  } else {  // max == b: h = 240 + 60 (r - g) / range
    const double d = (h - 240.0) / 60.0 * range;
    b = max;
    r = d >= 0 ? min + d : min;
    g = d >= 0 ? min : min - d;
  }
  auto byte = [](double x) { return static_cast<std::uint8_t>(std::lround(std::clamp(x, 0.0, 255.0))); };
  return {byte(b), byte(g), byte(r)};
}

Lab bgrToLab(std::uint8_t b, std::uint8_t g, std::uint8_t r) {
  const auto& lin = srgbToLinear();
  const double rgb[3] = {lin[r], lin[g], lin[b]};
  double f[3];
  for (int i = 0; i < 3; ++i) {
    const double xyz = kRgbToXyz[i][0] * rgb[0] + kRgbToXyz[i][1] * rgb[1] + kRgbToXyz[i][2] * rgb[2];
    f[i] = labF(xyz / kWhite[i]);
  }
  const double y = kRgbToXyz[1][0] * rgb[0] + kRgbToXyz[1][1] * rgb[1] + kRgbToXyz[1][2] * rgb[2];
  Lab lab;
  lab.l = y > kLabEpsilon ? 116.0 * f[1] - 16.0 : kLabKappa * y;
  lab.a = 500.0 * (f[0] - f[1]);
  lab.b = 200.0 * (f[1] - f[2]);
  return lab;
}

double labDistance(const Lab& x, const Lab& y) {
  return std::sqrt((x.l - y.l) * (x.l - y.l) + (x.a - y.a) * (x.a - y.a) + (x.b - y.b) * (x.b - y.b));
}

double hueDifference(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d <= -180.0) d += 360.0;
  if (d > 180.0) d -= 360.0;
  return d;
}

double hueDistance(double a, double b) { return std::abs(hueDifference(a, b)); }

}  // namespace soccer_vision
