// Segmentation results (core) -> soccer_vision/BlobArray messages, shared by the
// Segmentation nodelet and offline tools so that live topics and files carry the same data.
#pragma once

#include <vector>

#include <opencv2/core.hpp>
#include <sensor_msgs/RegionOfInterest.h>
#include <std_msgs/Header.h>

#include "soccer_vision/Blob.h"
#include "soccer_vision/BlobArray.h"
#include "soccer_vision/segmentation/region_extractor.h"
#include "soccer_vision/segmentation/segmenter.h"

namespace soccer_vision {

// One region (image pixel coordinates) as a Blob; bounding box fields saturate at 65535.
Blob toBlob(const Region& region);

// A rectangle (image pixels) as a RegionOfInterest (do_rectify false); negative parts are
// clipped to 0.
sensor_msgs::RegionOfInterest toRegionOfInterest(const cv::Rect& rect);
// The inverse (empty rectangle for width or height 0).
cv::Rect fromRegionOfInterest(const sensor_msgs::RegionOfInterest& roi);

// Fills `out` (header = the image's header: capture stamp, optical frame) from one frame's
// result: every region as a Blob in result order, the windows as used (empty on a global
// search), cap_hits per ColorClass value (kNumColorClasses entries), the processing time
// (result.timings.total_ms) in seconds and whether the image was a Bayer mosaic.
void toBlobArray(const SegmentationResult& result, const std_msgs::Header& header, int camera_id,
                 int image_width, int image_height, bool mosaic, BlobArray& out);

}  // namespace soccer_vision
