#include "soccer_vision/ros/blob_conversions.h"

#include <algorithm>
#include <cstdint>

namespace soccer_vision {

namespace {

std::uint16_t clampU16(int v) { return static_cast<std::uint16_t>(std::clamp(v, 0, 65535)); }

}  // namespace

Blob toBlob(const Region& region) {
  Blob b;
  b.color = static_cast<std::uint8_t>(region.color);
  b.area = region.area;
  b.cx = region.cx;
  b.cy = region.cy;
  b.mu20 = region.mu20;
  b.mu11 = region.mu11;
  b.mu02 = region.mu02;
  b.orientation = region.orientation;
  b.x0 = clampU16(region.bbox.x);
  b.y0 = clampU16(region.bbox.y);
  b.width = clampU16(region.bbox.width);
  b.height = clampU16(region.bbox.height);
  return b;
}

sensor_msgs::RegionOfInterest toRegionOfInterest(const cv::Rect& rect) {
  const int x0 = std::max(rect.x, 0), y0 = std::max(rect.y, 0);
  const int x1 = std::max(rect.x + rect.width, x0), y1 = std::max(rect.y + rect.height, y0);
  sensor_msgs::RegionOfInterest roi;
  roi.x_offset = static_cast<std::uint32_t>(x0);
  roi.y_offset = static_cast<std::uint32_t>(y0);
  roi.width = static_cast<std::uint32_t>(x1 - x0);
  roi.height = static_cast<std::uint32_t>(y1 - y0);
  roi.do_rectify = false;
  return roi;
}

cv::Rect fromRegionOfInterest(const sensor_msgs::RegionOfInterest& roi) {
  // Image sizes fit in int; larger values are clipped against the image by the segmenter.
  auto toInt = [](std::uint32_t v) { return static_cast<int>(std::min<std::uint32_t>(v, 1u << 30)); };
  return cv::Rect(toInt(roi.x_offset), toInt(roi.y_offset), toInt(roi.width), toInt(roi.height));
}

void toBlobArray(const SegmentationResult& result, const std_msgs::Header& header, int camera_id,
                 int image_width, int image_height, bool mosaic, BlobArray& out) {
  out.header = header;
  out.camera_id = static_cast<std::uint8_t>(std::clamp(camera_id, 0, 255));
  out.image_width = static_cast<std::uint32_t>(std::max(image_width, 0));
  out.image_height = static_cast<std::uint32_t>(std::max(image_height, 0));
  out.global_search = result.global_search;
  out.mosaic = mosaic;
  out.windows.clear();
  if (!result.global_search) {
    out.windows.reserve(result.windows.size());
    for (const cv::Rect& w : result.windows) out.windows.push_back(toRegionOfInterest(w));
  }
  out.blobs.clear();
  out.blobs.reserve(result.regions.size());
  for (const Region& r : result.regions) out.blobs.push_back(toBlob(r));
  out.cap_hits.assign(result.cap_hits.begin(), result.cap_hits.end());
  out.processing_time = static_cast<float>(result.timings.total_ms * 1e-3);
}

}  // namespace soccer_vision
