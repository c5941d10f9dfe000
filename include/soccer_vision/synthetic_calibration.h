// The colour table of a built-in synthetic camera, calibrated as a team calibrates a real
// one (calibrateColorTable) on a few frames of the first seconds of a scenario, with the
// simulator's sample polygons. Shared by calibrate_synthetic (the demo's start-up table)
// and the benchmarks.
#pragma once

#include "soccer_vision/color_table.h"
#include "soccer_vision/scenario.h"

namespace soccer_vision {

struct SyntheticCalibration {
  int frames = 6;                // calibration frames ...
  double seconds_between = 1.5;  // ... this far apart in scene time (one frame shows only
                                 // the robots and ball that happen to be in view)
};

// Bayer scenarios are calibrated on the quad colours of their mosaic frames
// (classifiedColors): what run-time classification will look up, noise and all. Throws
// like the renderer and calibrateColorTable.
ColorTable calibrateSyntheticCamera(ScenarioConfig scenario, int camera_index, const SyntheticCalibration& how = {});

}  // namespace soccer_vision
