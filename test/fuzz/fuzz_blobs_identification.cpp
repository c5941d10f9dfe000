// BlobArray -> identification (the Identification nodelet's path: fromBlobArray, then
// FrameIdentifier::identify with the default camera 0 and the two_tag and ssl patterns).
// Input: one flag byte (bit 0 global_search, bit 1 mosaic, bit 2 ssl pattern), then
// 61-byte blobs: color u8, area u32, cx cy mu20 mu11 mu02 orientation f64, x0 y0 width
// height u16 (little endian, as in memory), at most 1000.
#include <cstring>
#include <vector>

#include "fuzz_target.h"
#include "soccer_vision/BlobArray.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/ros/detection_conversions.h"

namespace {

template <typename T>
T take(const std::uint8_t*& p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  p += sizeof(T);
  return v;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace sv = soccer_vision;
  static const sv::FieldGeometry field;
  static const sv::CameraModel camera = sv::CameraModel::defaultCamera(field, 0);
  static const sv::FrameIdentifier two_tag(camera, sv::PatternSet::twoTag(), field);
  static const sv::FrameIdentifier ssl(camera, sv::PatternSet::ssl(), field);
  constexpr std::size_t kBlobBytes = 61;
  if (size < 1) return 0;
  const std::uint8_t flags = data[0];
  sv::BlobArray msg;
  msg.global_search = flags & 1;
  msg.mosaic = flags & 2;
  const std::uint8_t* p = data + 1;
  for (std::size_t left = size - 1; left >= kBlobBytes && msg.blobs.size() < 1000; left -= kBlobBytes) {
    sv::Blob b;
    b.color = take<std::uint8_t>(p);
    b.area = take<std::uint32_t>(p);
    b.cx = take<double>(p);
    b.cy = take<double>(p);
    b.mu20 = take<double>(p);
    b.mu11 = take<double>(p);
    b.mu02 = take<double>(p);
    b.orientation = take<double>(p);
    b.x0 = take<std::uint16_t>(p);
    b.y0 = take<std::uint16_t>(p);
    b.width = take<std::uint16_t>(p);
    b.height = take<std::uint16_t>(p);
    msg.blobs.push_back(b);
  }
  try {
    const sv::FrameIdentifier& identifier = flags & 4 ? ssl : two_tag;
    identifier.identify(sv::fromBlobArray(msg), 1.0, 0, msg.global_search);
  } catch (const std::exception&) {
  }
  return 0;
}
