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

// Appearance randomisation: how far a scene may look from the presets a system was tuned
// on. Each value is a magnitude; where and in which direction an effect acts (marker
// prints, carpet pattern, lamp positions, white-balance error, distractors) is drawn from
// the scenario's seed. All default to off.
struct AppearanceConfig {
  double marker_albedo_spread = 0.0;  // relative std-dev per channel of each printed marker
  double carpet_fibre = 0.0;          // relative std-dev of the carpet's per-pixel fibre texture
  double carpet_patches = 0.0;        // relative amplitude of worn / dirty patches (~0.5-2 m)
  double mowing_stripes = 0.0;        // relative amplitude of 0.5 m stripes along the length
  int lamps = 0;                      // point lamps over the field (0: the smooth light model only)
  double lamp_height = 6.0;           // m above the carpet
  double lamp_drift = 0.0;            // relative amplitude of each lamp's own slow drift
  double shadow = 0.0;                // share of a lamp's light a robot blocks in its (soft) shadow
  double color_temperature = 0.0;     // K of the light, white-balanced for 5500 K; 0 = neutral
  double white_balance_error = 0.0;   // relative red/blue gain error (direction from the seed)
  double gain = 1.0;                  // camera gain on the exposure
  double gamma = 1.0;                 // response exponent: out = 255 (in / 255)^gamma
  double saturation = 1.0;            // chroma scale about the pixel's grey value
  double vignetting = 0.0;            // light lost at the image corners (0.4: corners at 60 %)
  double lens_blur = 0.0;             // Gaussian sigma of the optics, px
  double shot_noise = 0.0;            // shot-noise variance per 8-bit unit of signal (DN)
  bool demosaic = false;              // with sensor.bayer: the camera's own demosaic, BGR out
  int distractors = 0;                // people's legs and shoes, clothes, cables outside the lines
  double ball_shading = 0.0;          // the ball lit as a sphere by the lamps (1) or evenly (0)
  double ball_gloss = 0.0;            // the ball's highlights: peak per unit of the light on its top
};

// Lens and mounting of the synthetic cameras beyond CameraModel::defaultCamera.
struct LensConfig {
  double k1 = -0.12, k2 = 0.02;  // radial distortion (plumb_bob), the built-in lens by default
  double tilt_deg = 0.0;         // camera tilted from straight down (direction from the seed)
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
  int cameras = 2;                  // cameras over the field (CameraModel::defaultCamera's layout)
  int blue_robots = 5;
  int yellow_robots = 5;
  int balls = 1;
  LightingConfig lighting;
  SensorConfig sensor;
  MotionConfig motion;
  AppearanceConfig appearance;
  LensConfig lens;
};

// Parses a scenario YAML document over the defaults; unknown keys are errors (typos in
// presets must not pass silently). Throws std::runtime_error with a clear message.
ScenarioConfig parseScenario(const std::string& yaml_text, const std::string& source_name);
ScenarioConfig loadScenario(const std::string& path);

// Limits of a scenario (docs/robustness.md), far above every preset (16 robots a team,
// 1 ball, 4 blur samples); the image size is at most kMaxImageSide (camera_model.h).
constexpr int kMaxScenarioRobots = 64;  // per team
constexpr int kMaxScenarioBalls = 16;
constexpr int kMaxBlurSamples = 64;  // renders per frame
// Throws std::runtime_error naming `source_name` and the field for values out of range;
// parseScenario calls it, and so must whoever changes a scenario afterwards (make_scenario's
// --width/--height).
void checkScenario(const ScenarioConfig& scenario, const std::string& source_name);

}  // namespace soccer_vision
