// Messages between segmentation, identification and tracking <-> core types, shared by
// the nodelets and the offline tools so that both see exactly the same data.
#pragma once

#include <vector>

#include <std_msgs/Header.h>

#include "soccer_vision/BlobArray.h"
#include "soccer_vision/CameraDetections.h"
#include "soccer_vision/detections.h"
#include "soccer_vision/region_extractor.h"

namespace soccer_vision {

// A Blob back as the Region it was made from (toBlob in blob_conversions.h); colours
// outside the ColorClass range become ColorClass::None.
Region fromBlob(const Blob& blob);
std::vector<Region> fromBlobArray(const BlobArray& blobs);

// One camera frame's detections as a message (header: capture stamp, frame "field";
// velocities 0, `visible` true) and back (stamp and camera id from the message).
void toCameraDetections(const CameraFrameDetections& detections, const std_msgs::Header& header,
                        CameraDetections& out);
CameraFrameDetections fromCameraDetections(const CameraDetections& msg);

}  // namespace soccer_vision
