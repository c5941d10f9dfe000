// Scenario presets (config/scenarios/*.yaml): what the synthetic camera shows and how
// realistic the picture is. Every field has a default; an empty YAML is the embedded
// default scenario (even light, moving robots, two-tag pattern, 5 + 5 robots).
#pragma once

#include <cstdint>
#include <string>

namespace soccer_vision {

struct LightingConfig {
  double brightness = 1.0;       // global gain on the albedo
  double uneven_ratio = 1.0;     // brightest / darkest carpet illumination over the field
  double drift_amplitude = 0.0;  // relative amplitude of the slow global drift
  double drift_period = 20.0;    // s
  double flicker = 0.0;          // relative std-dev of the per-frame gain (mains flicker)
};

struct SensorConfig {
  double noise_sigma = 1.0;  // std-dev of additive Gaussian noise, 8-bit units
  double exposure = 0.004;   // s, integration time (motion blur when blur_samples > 1)
  int blur_samples = 1;      // sub-exposures averaged for motion blur (1 = off)
  std::string bayer;         // "", "rggb", "bggr", "gbrg" or "grbg": mosaic output
  int jpeg_quality = 0;      // 1..100: JPEG round trip artefacts; 0 = off
};

struct MotionConfig {
  double robot_max_speed = 2.0;                // m/s (<= 5)
  double robot_max_accel = 3.0;                // m/s^2
  double robot_max_omega = 4.0;                // rad/s
  double ball_max_speed = 6.0;                 // m/s (<= 15), speed of kicks
  double ball_friction = 0.4;                  // m/s^2 rolling deceleration
  double kick_interval = 1.5;                  // s, mean time between kicks
  double min_separation = 0.02;                // m, minimum gap between robot bodies (0 = touching)
  double area_x_min = -4.5, area_x_max = 4.5;  // m, where robots play
  double area_y_min = -3.0, area_y_max = 3.0;
};

struct ScenarioConfig {
  std::string name = "default";
  std::uint64_t seed = 1;
  double fps = 60.0;
  int width = 1280;  // pixels
  int height = 1024;
  std::string pattern = "two_tag";  // pattern set name or YAML path
  std::string field = "div_b";      // field geometry: div_b, div_a or a YAML path (config/fields/)
  int blue_robots = 5;
  int yellow_robots = 5;
  int balls = 1;
  LightingConfig lighting;
  SensorConfig sensor;
  MotionConfig motion;
};

// Parses a scenario YAML document over the defaults; unknown keys are errors (typos in
// presets must not pass silently). Throws std::runtime_error with a clear message.
ScenarioConfig parseScenario(const std::string& yaml_text, const std::string& source_name);
ScenarioConfig loadScenario(const std::string& path);

}  // namespace soccer_vision
