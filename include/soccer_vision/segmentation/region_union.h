// One region made of several of one colour: the parts of a marker or of a ball's streak
// that segmentation cut apart (a row of pixels its colour class missed).
#pragma once

#include <vector>

#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

// The union of `parts` (the first's colour): areas summed, centroid area-weighted, central
// second moments by the parallel-axis theorem, orientation from those, bbox the union of
// the bboxes. Throws std::invalid_argument when `parts` is empty.
Region regionUnion(const std::vector<const Region*>& parts);

}  // namespace soccer_vision
