#include "soccer_vision/simulation/synthetic_calibration.h"

#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"

namespace soccer_vision {

ColorTable calibrateSyntheticCamera(ScenarioConfig scenario, int camera_index,
                                    const SyntheticCalibration& how) {
  const std::optional<PixelLayout> layout =
      scenario.sensor.bayer.empty() || scenario.appearance.demosaic
          ? PixelLayout::Bgr
          : pixelLayoutForEncoding("bayer_" + scenario.sensor.bayer + "8");
  if (!layout) throw std::invalid_argument("unknown Bayer pattern '" + scenario.sensor.bayer + "'");
  const FieldGeometry field = fieldGeometryByName(scenario.field);
  const PatternSet patterns = patternSetByName(scenario.pattern);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const FieldRenderer renderer(scenarioCamera(field, camera_index, scenario), field, patterns, scenario);
  std::vector<CalibrationImage> images;
  const int steps_between = static_cast<int>(std::lround(how.seconds_between * scenario.fps));
  for (int i = 0; i < how.frames; ++i) {
    RenderedFrame frame;
    renderer.render(sim.state(), static_cast<std::int64_t>(i) * steps_between, frame);
    // Polygons at the start of the exposure would sample a fast ball's streak at its tail
    // (a blend with the carpet) and the trailing edges of moving markers.
    const SceneState shown = extrapolate(sim.state(), shownTimeAfterStamp(scenario.sensor));
    images.push_back({classifiedColors(frame.image, *layout), renderer.paintedSamples(shown)});
    for (int k = 0; k < steps_between; ++k) sim.step(1.0 / scenario.fps);
  }
  return calibrateColorTable(images);
}

}  // namespace soccer_vision
