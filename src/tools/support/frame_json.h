// What the pipeline saw in one frame, as JSON: the segmented regions, identification's
// detections and rejections, and the tracker's tracks. detect prints the first two for one
// image; evaluate --trace writes all of it for every frame of a recording, to find out why a
// robot or the ball was missed in frame N without a debugger.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "soccer_vision/common/detections.h"
#include "soccer_vision/pipeline/vision_pipeline.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

// Each region: color, area [px], centroid cx, cy, bounding box x, y, w, h (image pixels), the
// principal standard deviations sd [major, minor] [px] and the major axis' angle [rad].
nlohmann::json regionsJson(const std::vector<Region>& regions);

// robots (team, id, x, y, theta, u, v, confidence), balls (x, y, u, v, area, confidence; the
// candidates, best first), rejections by cause (every cause) and the rejected robot candidates (u, v,
// cause). Without a camera pose (`placed` false) x, y and theta are null.
nlohmann::json detectionsJson(const CameraFrameDetections& detections, bool placed = true);

// One frame of the pipeline: stamp, camera, how it was searched (global or windows, why,
// how many rectangles), its regions and detections, the tracks as output (what consumers
// got: visible, primary) and every track the tracker holds at the frame's stamp (withheld
// ones too) with its position std-dev [mm] and the time since its last measurement [s].
nlohmann::json frameTraceJson(const PipelineFrame& frame, const Tracker& tracker);

}  // namespace soccer_vision
