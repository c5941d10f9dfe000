#include "soccer_vision/simulation/scenario.h"

#include <functional>
#include <map>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

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
    };
    return *this;
  }
  MapReader& section(const std::string& key, std::function<void(const YAML::Node&)> read) {
    readers_[key] = std::move(read);
    return *this;
  }
  void read() const {
    if (!node_) return;
    for (const auto& kv : node_) {
      const auto key = kv.first.as<std::string>();
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
  MapReader(root, "", source)
      .field("name", s.name)
      .field("seed", s.seed)
      .field("fps", s.fps)
      .field("width", s.width)
      .field("field", s.field)
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

  check(s.fps > 0 && s.fps <= 1000, source, "fps must be in (0, 1000]");
  check(s.width >= 64 && s.height >= 64 && s.width % 2 == 0 && s.height % 2 == 0, source,
        "width and height must be even and at least 64");
  check(s.blue_robots >= 0 && s.yellow_robots >= 0 && s.balls >= 0, source,
        "robot and ball counts must not be negative");
  check(l.brightness > 0 && l.uneven_ratio >= 1.0, source,
        "lighting.brightness must be > 0 and lighting.uneven_ratio >= 1");
  check(l.drift_amplitude >= 0 && l.drift_amplitude < 1 && l.flicker >= 0 && l.flicker < 0.5 &&
            l.drift_period > 0,
        source, "lighting drift/flicker out of range");
  check(c.noise_sigma >= 0 && c.exposure >= 0 && c.blur_samples >= 1, source,
        "sensor.noise_sigma/exposure must be >= 0 and sensor.blur_samples >= 1");
  check(c.bayer.empty() || c.bayer == "rggb" || c.bayer == "bggr" || c.bayer == "gbrg" || c.bayer == "grbg",
        source, "sensor.bayer must be one of rggb, bggr, gbrg, grbg");
  check(c.jpeg_quality >= 0 && c.jpeg_quality <= 100, source, "sensor.jpeg_quality must be 0..100");
  check(m.robot_max_speed >= 0 && m.robot_max_speed <= 5.0, source,
        "motion.robot_max_speed must be in [0, 5] m/s");
  check(m.ball_max_speed >= 0 && m.ball_max_speed <= 15.0, source,
        "motion.ball_max_speed must be in [0, 15] m/s");
  check(m.area_x_min < m.area_x_max && m.area_y_min < m.area_y_max, source, "motion area is empty");
  return s;
}

ScenarioConfig loadScenario(const std::string& path) { return parseScenario(readTextFile(path), path); }

}  // namespace soccer_vision
