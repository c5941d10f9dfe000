#include "soccer_vision/simulation/scenario.h"

#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <type_traits>

#include <yaml-cpp/yaml.h>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {
namespace {

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error("scenario " + source + ": " + what);
}

// Reads the keys of one YAML map into fields; any key without a reader is an error.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string path, const std::string& source)
      : node_(node), path_(std::move(path)), source_(source) {
    if (node_ && !node_.IsMap()) fail(source_, "'" + path_ + "' must be a map");
  }
  template <typename T>
  MapReader& field(const std::string& key, T& value) {
    readers_[key] = [this, key, &value](const YAML::Node& n) {
      try {
        value = n.as<T>();
      } catch (const YAML::Exception&) {
        fail(source_, "'" + path_ + key + "' has the wrong type");
      }
      if constexpr (std::is_floating_point_v<T>) {
        if (!std::isfinite(value)) fail(source_, "'" + path_ + key + "' must be a finite number");
      }
    };
    return *this;
  }
  MapReader& section(const std::string& key, std::function<void(const YAML::Node&)> read) {
    readers_[key] = std::move(read);
    return *this;
  }
  void read() const {
    if (!node_) return;
    std::set<std::string> seen;  // YAML forbids duplicate keys; yaml-cpp keeps the first
    for (const auto& kv : node_) {
      const auto key = kv.first.as<std::string>();
      if (!seen.insert(key).second) fail(source_, "duplicate key '" + path_ + key + "'");
      const auto it = readers_.find(key);
      if (it == readers_.end()) fail(source_, "unknown key '" + path_ + key + "'");
      it->second(kv.second);
    }
  }

 private:
  YAML::Node node_;
  std::string path_;
  const std::string& source_;
  std::map<std::string, std::function<void(const YAML::Node&)>> readers_;
};

void check(bool ok, const std::string& source, const std::string& what) {
  if (!ok) fail(source, what);
}

}  // namespace

ScenarioConfig parseScenario(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    fail(source, std::string("invalid YAML: ") + e.what());
  }
  ScenarioConfig s;
  if (root.IsNull()) return s;
  check(root.IsMap(), source, "top level must be a map");
  auto& l = s.lighting;
  auto& c = s.sensor;
  auto& m = s.motion;
  auto& a = s.appearance;
  MapReader(root, "", source)
      .field("name", s.name)
      .field("seed", s.seed)
      .field("fps", s.fps)
      .field("width", s.width)
      .field("field", s.field)
      .field("cameras", s.cameras)
      .field("height", s.height)
      .field("pattern", s.pattern)
      .field("blue_robots", s.blue_robots)
      .field("yellow_robots", s.yellow_robots)
      .field("balls", s.balls)
      .section("lighting",
               [&](const YAML::Node& n) {
                 MapReader(n, "lighting.", source)
                     .field("brightness", l.brightness)
                     .field("uneven_ratio", l.uneven_ratio)
                     .field("drift_amplitude", l.drift_amplitude)
                     .field("drift_period", l.drift_period)
                     .field("flicker", l.flicker)
                     .read();
               })
      .section("sensor",
               [&](const YAML::Node& n) {
                 MapReader(n, "sensor.", source)
                     .field("noise_sigma", c.noise_sigma)
                     .field("exposure", c.exposure)
                     .field("blur_samples", c.blur_samples)
                     .field("bayer", c.bayer)
                     .field("jpeg_quality", c.jpeg_quality)
                     .read();
               })
      .section("appearance",
               [&](const YAML::Node& n) {
                 MapReader(n, "appearance.", source)
                     .field("marker_albedo_spread", a.marker_albedo_spread)
                     .field("carpet_fibre", a.carpet_fibre)
                     .field("carpet_patches", a.carpet_patches)
                     .field("mowing_stripes", a.mowing_stripes)
                     .field("lamps", a.lamps)
                     .field("lamp_height", a.lamp_height)
                     .field("lamp_drift", a.lamp_drift)
                     .field("shadow", a.shadow)
                     .field("color_temperature", a.color_temperature)
                     .field("white_balance_error", a.white_balance_error)
                     .field("gain", a.gain)
                     .field("gamma", a.gamma)
                     .field("saturation", a.saturation)
                     .field("vignetting", a.vignetting)
                     .field("lens_blur", a.lens_blur)
                     .field("shot_noise", a.shot_noise)
                     .field("demosaic", a.demosaic)
                     .field("distractors", a.distractors)
                     .field("ball_shading", a.ball_shading)
                     .field("ball_gloss", a.ball_gloss)
                     .read();
               })
      .section("lens",
               [&](const YAML::Node& n) {
                 MapReader(n, "lens.", source)
                     .field("k1", s.lens.k1)
                     .field("k2", s.lens.k2)
                     .field("tilt_deg", s.lens.tilt_deg)
                     .read();
               })
      .section("motion",
               [&](const YAML::Node& n) {
                 MapReader(n, "motion.", source)
                     .field("robot_max_speed", m.robot_max_speed)
                     .field("robot_max_accel", m.robot_max_accel)
                     .field("robot_max_omega", m.robot_max_omega)
                     .field("ball_max_speed", m.ball_max_speed)
                     .field("ball_friction", m.ball_friction)
                     .field("kick_interval", m.kick_interval)
                     .field("min_separation", m.min_separation)
                     .field("area_x_min", m.area_x_min)
                     .field("area_x_max", m.area_x_max)
                     .field("area_y_min", m.area_y_min)
                     .field("area_y_max", m.area_y_max)
                     .read();
               })
      .read();

  checkScenario(s, source);
  return s;
}

void checkScenario(const ScenarioConfig& s, const std::string& source) {
  const auto& l = s.lighting;
  const auto& c = s.sensor;
  const auto& m = s.motion;
  const auto& a = s.appearance;
  check(s.fps > 0 && s.fps <= 1000, source, "fps must be in (0, 1000]");
  check(s.width >= 64 && s.height >= 64 && s.width % 2 == 0 && s.height % 2 == 0 &&
            s.width <= kMaxImageSide && s.height <= kMaxImageSide,
        source, "width and height must be even and in 64.." + std::to_string(kMaxImageSide));
  check(s.cameras >= 1 && s.cameras <= kMaxCameras, source,
        "cameras must be in 1.." + std::to_string(kMaxCameras));
  check(s.blue_robots >= 0 && s.yellow_robots >= 0 && s.balls >= 0, source,
        "robot and ball counts must not be negative");
  check(s.blue_robots <= kMaxScenarioRobots && s.yellow_robots <= kMaxScenarioRobots, source,
        "blue_robots and yellow_robots must be at most " + std::to_string(kMaxScenarioRobots));
  check(s.balls <= kMaxScenarioBalls, source, "balls must be at most " + std::to_string(kMaxScenarioBalls));
  check(l.brightness > 0 && l.uneven_ratio >= 1.0, source,
        "lighting.brightness must be > 0 and lighting.uneven_ratio >= 1");
  check(l.drift_amplitude >= 0 && l.drift_amplitude < 1 && l.flicker >= 0 && l.flicker < 0.5 &&
            l.drift_period > 0,
        source, "lighting drift/flicker out of range");
  check(c.noise_sigma >= 0 && c.exposure >= 0 && c.exposure <= 1.0 && c.blur_samples >= 1 &&
            c.blur_samples <= kMaxBlurSamples,
        source,
        "sensor.noise_sigma must be >= 0, sensor.exposure in [0, 1] s and sensor.blur_samples in 1.." +
            std::to_string(kMaxBlurSamples));
  check(c.bayer.empty() || c.bayer == "rggb" || c.bayer == "bggr" || c.bayer == "gbrg" || c.bayer == "grbg",
        source, "sensor.bayer must be one of rggb, bggr, gbrg, grbg");
  check(c.jpeg_quality >= 0 && c.jpeg_quality <= 100, source, "sensor.jpeg_quality must be 0..100");
  check(m.robot_max_speed >= 0 && m.robot_max_speed <= 5.0, source,
        "motion.robot_max_speed must be in [0, 5] m/s");
  check(m.ball_max_speed >= 0 && m.ball_max_speed <= 15.0, source,
        "motion.ball_max_speed must be in [0, 15] m/s");
  check(a.marker_albedo_spread >= 0 && a.marker_albedo_spread <= 0.3, source,
        "appearance.marker_albedo_spread must be in [0, 0.3]");
  check(a.carpet_fibre >= 0 && a.carpet_fibre <= 0.3 && a.carpet_patches >= 0 && a.carpet_patches <= 0.5 &&
            a.mowing_stripes >= 0 && a.mowing_stripes <= 0.5,
        source, "appearance.carpet_fibre must be in [0, 0.3], carpet_patches and mowing_stripes in [0, 0.5]");
  check(a.lamps >= 0 && a.lamps <= 16, source, "appearance.lamps must be in [0, 16]");
  check(a.lamp_height >= 2 && a.lamp_height <= 30, source, "appearance.lamp_height must be in [2, 30] m");
  check(a.lamp_drift >= 0 && a.lamp_drift < 1 && a.shadow >= 0 && a.shadow <= 1, source,
        "appearance.lamp_drift must be in [0, 1), appearance.shadow in [0, 1]");
  check(a.color_temperature == 0 || (a.color_temperature >= 2000 && a.color_temperature <= 10000), source,
        "appearance.color_temperature must be 0 (neutral) or in [2000, 10000] K");
  check(a.white_balance_error >= 0 && a.white_balance_error <= 0.5, source,
        "appearance.white_balance_error must be in [0, 0.5]");
  check(a.gain > 0 && a.gain <= 4 && a.gamma >= 0.3 && a.gamma <= 3 && a.saturation >= 0 && a.saturation <= 2,
        source, "appearance.gain must be in (0, 4], gamma in [0.3, 3], saturation in [0, 2]");
  check(a.vignetting >= 0 && a.vignetting < 1 && a.lens_blur >= 0 && a.lens_blur <= 5 && a.shot_noise >= 0 &&
            a.shot_noise <= 10,
        source, "appearance.vignetting must be in [0, 1), lens_blur in [0, 5] px, shot_noise in [0, 10]");
  check(!a.demosaic || !c.bayer.empty(), source, "appearance.demosaic needs sensor.bayer");
  check(a.distractors >= 0 && a.distractors <= 64, source, "appearance.distractors must be in [0, 64]");
  check(a.ball_shading >= 0 && a.ball_shading <= 1 && a.ball_gloss >= 0 && a.ball_gloss <= 2, source,
        "appearance.ball_shading must be in [0, 1], ball_gloss in [0, 2]");
  check(s.lens.k1 >= -0.4 && s.lens.k1 <= 0.1 && s.lens.k2 >= -0.1 && s.lens.k2 <= 0.2, source,
        "lens.k1 must be in [-0.4, 0.1], lens.k2 in [-0.1, 0.2]");
  check(s.lens.tilt_deg >= 0 && s.lens.tilt_deg <= 15, source, "lens.tilt_deg must be in [0, 15]");
  check(m.area_x_min < m.area_x_max && m.area_y_min < m.area_y_max, source, "motion area is empty");
}

ScenarioConfig loadScenario(const std::string& path) { return parseScenario(readTextFile(path), path); }

}  // namespace soccer_vision
