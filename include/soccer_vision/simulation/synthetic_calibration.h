// The colour table of a built-in synthetic camera, calibrated as a team calibrates a real
// one (calibrateColorTable) on frames of the first seconds of a scenario, with the
// simulator's sample polygons. Shared by calibrate_synthetic (the demo's start-up table)
// and the benchmarks.
#pragma once

#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/simulation/scenario.h"

namespace soccer_vision {

struct SyntheticCalibration {
  // Calibration frames, this far apart in scene time: one frame shows only the robots and
  // ball that happen to be in view, about two markers of each role colour. Measured on
  // flicker_noise (Bayer, noise sigma 4, JPEG): 6 frames x 1.5 s leave HS cells of the
  // role colours unsampled, 58-75 % of the quads inside a role marker classified as
  // it, 49 % of the robots identified per frame, 97.2 % tracked; 24 x 0.375 s: 84-94 %
  // of the quads, 83 %, 99.87 % tracked (the same 9 s of the scenario, 2.4 s instead of
  // 0.9 s of start-up).
  int frames = 24;
  double seconds_between = 0.375;
};

// Bayer scenarios are calibrated on the quad colours of their mosaic frames
// (classifiedColors): what run-time classification will look up, noise and all. The
// sample polygons are placed where each frame shows the objects: a frame rendered with
// motion blur shows them averaged over the exposure, centred at its middle (the capture
// stamp is its start), so the polygons come from the scene at shownTimeAfterStamp (field_renderer.h).
// Throws like the renderer and calibrateColorTable.
ColorTable calibrateSyntheticCamera(ScenarioConfig scenario, int camera_index,
                                    const SyntheticCalibration& how = {});

}  // namespace soccer_vision
