// calibrate_synthetic: the colour table of the built-in synthetic camera, calibrated
// exactly as a team calibrates a real one (calibrate_colors' method) on frames of the first
// seconds of a scenario (6 frames, 1.5 s apart), with the simulator's sample polygons (markers, ball, carpet,
// lines, robot tops) instead of hand-drawn ones. The demo launch runs it at start-up so that the pipeline has
// a table without any file shipped.
//
//   rosrun soccer_vision calibrate_synthetic --out table.svct [--scenario NAME|FILE.yaml]
//       (also --key=value)
//       [--camera 0] [--width W --height H]
//
// Bayer scenarios are calibrated on the colour image the mosaic samples (the classifier
// reads each 2x2 quad as one colour). The file is written to a temporary name and renamed,
// so a reader never sees half a table. Exit status 0, or 2 with a message.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "soccer_vision/ros/package_paths.h"
#include "soccer_vision/simulation/scenario.h"
#include "soccer_vision/simulation/synthetic_calibration.h"

namespace sv = soccer_vision;

namespace {

struct Options {
  std::string out, scenario;
  int camera = 0, width = 0, height = 0;
};

int toInt(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty())
    throw std::invalid_argument(option + " needs an integer, got '" + text + "'");
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a.rfind("__", 0) == 0) continue;  // roslaunch's __name:= and __log:= remappings
    // --key=value (an empty value survives roslaunch's argument splitting only this way).
    std::optional<std::string> inline_value;
    if (const auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
      inline_value = a.substr(eq + 1);
      a = a.substr(0, eq);
    }
    auto value = [&]() -> std::string {
      if (inline_value) return *inline_value;
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--out")
      o.out = value();
    else if (a == "--scenario")
      o.scenario = value();
    else if (a == "--camera")
      o.camera = toInt(a, value());
    else if (a == "--width")
      o.width = toInt(a, value());
    else if (a == "--height")
      o.height = toInt(a, value());
    else
      throw std::invalid_argument("unknown argument '" + a +
                                  "' (--out, --scenario, --camera, --width, --height)");
  }
  if (o.out.empty()) throw std::invalid_argument("--out is required");
  if (o.camera < 0 || o.camera > 1) throw std::invalid_argument("--camera must be 0 or 1");
  if (o.width < 0 || o.height < 0) throw std::invalid_argument("--width/--height must be >= 0");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    const std::string path = sv::resolveScenarioPath(o.scenario);
    sv::ScenarioConfig scenario = path.empty() ? sv::ScenarioConfig{} : sv::loadScenario(path);
    if (o.width > 0) scenario.width = o.width;
    if (o.height > 0) scenario.height = o.height;
    const sv::ColorTable table = sv::calibrateSyntheticCamera(scenario, o.camera);
    const std::string temporary = o.out + ".partial";
    table.save(temporary);
    if (std::rename(temporary.c_str(), o.out.c_str()) != 0)
      throw std::runtime_error("cannot rename " + temporary + " to " + o.out);
    std::printf(
        "colour table of synthetic camera %d (%s, %dx%d) written to %s: %d overlap cells decided by Bayes\n",
        o.camera, scenario.name.empty() ? "embedded default" : scenario.name.c_str(), scenario.width,
        scenario.height, o.out.c_str(), static_cast<int>(table.statistics().overlap_cells));
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "calibrate_synthetic: " << e.what() << "\n";
    return 2;
  }
}
