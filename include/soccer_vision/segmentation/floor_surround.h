// What lies around a region: the share of a ring just outside its outline that the colour
// table reads as the floor (carpet or a field line). A ball lies on the floor; the streak
// table, which takes a ball's blurred mixture with the carpet for orange, reads some prints
// that way too (a yellow tag), and a print sits on a robot's dark top.
#pragma once

#include <optional>

#include "soccer_vision/segmentation/pixel_classifier.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

// Points of the ring sampled (evenly in angle).
constexpr int kFloorRingPoints = 24;

// The share [0, 1] of the ring's points inside the label image that `colors` classifies as
// Carpet or Line. The ring is the region's moment ellipse (semi-axes twice its principal
// standard deviations: a uniform ellipse's own outline) grown by max(2, its minor standard
// deviation) label pixels, so that it clears a blurred edge. `region` in label coordinates.
// Empty when no point of the ring lies in the image.
std::optional<double> floorShareAround(const FrameClassifier& colors, const Region& region);

}  // namespace soccer_vision
