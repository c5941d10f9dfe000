#include "soccer_vision/calibration/field_line_pixels.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace soccer_vision {

std::vector<FieldLinePixel> detectFieldLinePixels(const cv::Mat& bgr, const FieldLinePixelParams& params) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw std::invalid_argument("field line pixels need a BGR image");
  const double sigma = params.sigma > 0 ? params.sigma : 1.5 * std::max(1.0, bgr.cols / 1280.0);
  cv::Mat channels[3], white;
  cv::split(bgr, channels);
  cv::min(channels[0], channels[1], white);
  cv::min(white, channels[2], white);
  cv::Mat w;
  white.convertTo(w, CV_32F);
  // The local background: the whiteness of the carpet around, without the thin lines.
  const int k = 2 * static_cast<int>(std::ceil(6 * sigma)) + 1;
  cv::Mat background;
  cv::medianBlur(white, background, std::min(k | 1, 255));
  cv::Mat smooth;
  cv::GaussianBlur(w, smooth, cv::Size(0, 0), sigma);
  cv::Mat gx, gy, gxx, gyy, gxy;
  cv::Sobel(smooth, gx, CV_32F, 1, 0, 3, 1.0 / 8);
  cv::Sobel(smooth, gy, CV_32F, 0, 1, 3, 1.0 / 8);
  cv::Sobel(smooth, gxx, CV_32F, 2, 0, 3, 1.0 / 4);
  cv::Sobel(smooth, gyy, CV_32F, 0, 2, 3, 1.0 / 4);
  cv::Sobel(smooth, gxy, CV_32F, 1, 1, 3, 1.0 / 4);
  // A bright bar of contrast c has a curvature of about -c / (sqrt(2 pi) sigma^3) at its
  // centre when it is narrower than sigma: ask for a quarter of the least contrast's.
  const double min_curvature = 0.25 * params.min_contrast / (std::sqrt(2 * M_PI) * sigma * sigma * sigma);
  std::vector<FieldLinePixel> out;
  const int border = static_cast<int>(std::ceil(3 * sigma)) + 1;
  for (int y = border; y < bgr.rows - border; ++y) {
    const float* pxx = gxx.ptr<float>(y);
    const float* pyy = gyy.ptr<float>(y);
    const float* pxy = gxy.ptr<float>(y);
    const float* px = gx.ptr<float>(y);
    const float* py = gy.ptr<float>(y);
    const float* pw = w.ptr<float>(y);
    const std::uint8_t* pb = background.ptr<std::uint8_t>(y);
    for (int x = border; x < bgr.cols - border; ++x) {
      const double contrast = pw[x] - pb[x];
      if (contrast < params.min_contrast) continue;
      // Most negative eigenvalue of the Hessian and its eigenvector: across the ridge.
      const double a = pxx[x], b = pxy[x], c = pyy[x];
      const double mean = 0.5 * (a + c), diff = std::sqrt(0.25 * (a - c) * (a - c) + b * b);
      const double lambda = mean - diff;
      if (lambda > -min_curvature) continue;
      Eigen::Vector2d n = std::abs(b) > 1e-12 ? Eigen::Vector2d(b, lambda - a)
                                              : (a < c ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(0, 1));
      n.normalize();
      const double t = -(px[x] * n.x() + py[x] * n.y()) / lambda;
      const Eigen::Vector2d offset = t * n;
      if (std::abs(offset.x()) > 0.5 || std::abs(offset.y()) > 0.5) continue;
      out.push_back({Eigen::Vector2d(x + offset.x(), y + offset.y()), n, contrast});
    }
  }
  if (params.max_points > 0 && static_cast<int>(out.size()) > params.max_points) {
    std::vector<FieldLinePixel> thinned;
    const double step = static_cast<double>(out.size()) / params.max_points;
    for (int i = 0; i < params.max_points; ++i) thinned.push_back(out[static_cast<std::size_t>(i * step)]);
    out.swap(thinned);
  }
  return out;
}

}  // namespace soccer_vision
