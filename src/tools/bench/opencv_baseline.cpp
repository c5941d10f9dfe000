#include "opencv_baseline.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace soccer_vision {

OpenCvBaseline::OpenCvBaseline(const ColorTable& table) {
  const auto& stats = table.statistics().classes;
  for (int c = static_cast<int>(ColorClass::Blue); c <= static_cast<int>(ColorClass::Orange); ++c) {
    const ClassStatistics& s = stats[c];
    if (s.valid == 0) continue;
    const double k = 2.5;
    const double h_half = std::min(90.0, k * std::sqrt(s.var_h)) / 2;  // degrees -> OpenCV units
    const double h = s.mean_h_valid / 2;
    const double s_lo = std::max(0.0, (s.mean_s - k * std::sqrt(s.var_s)) * 255);
    const double s_hi = std::min(255.0, (s.mean_s + k * std::sqrt(s.var_s)) * 255);
    const double v_lo = std::max(0.0, s.mean_v - k * std::sqrt(s.var_v));
    const double v_hi = std::min(255.0, s.mean_v + k * std::sqrt(s.var_v));
    ClassRange range;
    const double lo = h - h_half, hi = h + h_half;
    if (lo < 0) {
      range.ranges.push_back({cv::Scalar(0, s_lo, v_lo), cv::Scalar(hi, s_hi, v_hi)});
      range.ranges.push_back({cv::Scalar(180 + lo, s_lo, v_lo), cv::Scalar(179, s_hi, v_hi)});
    } else if (hi > 179) {
      range.ranges.push_back({cv::Scalar(lo, s_lo, v_lo), cv::Scalar(179, s_hi, v_hi)});
      range.ranges.push_back({cv::Scalar(0, s_lo, v_lo), cv::Scalar(hi - 180, s_hi, v_hi)});
    } else {
      range.ranges.push_back({cv::Scalar(lo, s_lo, v_lo), cv::Scalar(hi, s_hi, v_hi)});
    }
    classes_.push_back(range);
  }
}

std::uint64_t OpenCvBaseline::run(const cv::Mat& bgr) const {
  static const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::cvtColor(bgr, hsv_, cv::COLOR_BGR2HSV);
  std::uint64_t regions = 0;
  for (const auto& c : classes_) {
    cv::inRange(hsv_, c.ranges[0].first, c.ranges[0].second, mask_);
    for (std::size_t i = 1; i < c.ranges.size(); ++i) {
      cv::inRange(hsv_, c.ranges[i].first, c.ranges[i].second, part_);
      cv::bitwise_or(mask_, part_, mask_);
    }
    cv::morphologyEx(mask_, morph_, cv::MORPH_OPEN, kernel);
    cv::morphologyEx(morph_, mask_, cv::MORPH_CLOSE, kernel);
    regions += cv::connectedComponentsWithStats(mask_, labels_, stats_, centroids_, 8, CV_32S) - 1;
  }
  return regions;
}

}  // namespace soccer_vision
