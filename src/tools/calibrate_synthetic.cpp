// calibrate_synthetic: the colour table of the built-in synthetic camera, calibrated
// exactly as a team calibrates a real one (calibrate_colors' method) on frames of the first
// seconds of a scenario (24 frames, 0.375 s apart), with the simulator's sample polygons (markers, ball,
// carpet, lines, robot tops) instead of hand-drawn ones. The demo launch runs it at start-up so that the
// pipeline has a table without any file shipped.
//
//   rosrun soccer_vision calibrate_synthetic --out table.svct [--scenario NAME|FILE.yaml]
//       [--camera 0] [--width W --height H]
//   rosrun soccer_vision calibrate_synthetic --out PREFIX --cameras N ...   (cameras 0..N-1 of the
//       scenario's layout, each on its own thread, to PREFIX_<n>.svct: the demo's start-up)
//   ... --remove-on-exit   (stay until SIGINT, SIGTERM or SIGHUP, then remove the tables: the
//       demo's start-up tables live as long as its launch and leave nothing behind)
// (also --key=value; an empty --scenario= is the embedded scenario; roslaunch's __name:=
// remappings are ignored)
//
// Bayer scenarios are calibrated on the colour image the mosaic samples (the classifier
// reads each 2x2 quad as one colour). The file is written to a temporary name and renamed,
// so a reader never sees half a table. Exit status 0, or 2 with a message.
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <future>
#include <iostream>
#include <optional>
#include <pthread.h>
#include <signal.h>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/ros/package_paths.h"
#include "soccer_vision/simulation/scenario.h"
#include "soccer_vision/simulation/synthetic_calibration.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;

namespace {

struct Options {
  std::string out, scenario;
  int camera = 0, cameras = 0, width = 0, height = 0;
  bool remove_on_exit = false;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--out", o.out, "the colour table to write (.svct)")->required();
  app.add_option("--scenario", o.scenario,
                 "scenario preset: a name or a YAML file (default: the embedded one)");
  auto* one = app.add_option("--camera", o.camera, "synthetic camera of the scenario's layout")
                  ->check(CLI::Range(0, sv::kMaxCameras - 1))
                  ->capture_default_str();
  app.add_option("--cameras", o.cameras, "calibrate cameras 0..N-1; --out is then a prefix: PREFIX_<n>.svct")
      ->check(CLI::Range(1, sv::kMaxCameras))
      ->excludes(one);
  app.add_option("--width", o.width, "[px] image width; 0: the scenario's")->check(CLI::Range(0, 16384));
  app.add_option("--height", o.height, "[px] image height; 0: the scenario's")->check(CLI::Range(0, 16384));
  app.add_flag("--remove-on-exit", o.remove_on_exit,
               "stay until SIGINT, SIGTERM or SIGHUP (roslaunch's shutdown), then remove the tables written");
}

// The signals that end a launch. Blocked before any thread starts (threads inherit the mask),
// so that only sigwait takes them.
sigset_t endingSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"calibrate_synthetic: the colour table of a synthetic camera (docs/tools.md)",
               "calibrate_synthetic"};
  addOptions(app, o);
  if (const auto status = sv::parseLaunchedCommandLine(app, argc, argv)) return *status;
  const sigset_t ending = endingSignals();
  if (o.remove_on_exit) pthread_sigmask(SIG_BLOCK, &ending, nullptr);
  try {
    const std::string path = sv::resolveScenarioPath(o.scenario);
    sv::ScenarioConfig scenario = path.empty() ? sv::ScenarioConfig{} : sv::loadScenario(path);
    if (o.width > 0) scenario.width = o.width;
    if (o.height > 0) scenario.height = o.height;
    std::vector<std::pair<int, std::string>> jobs = {{o.camera, o.out}};
    if (o.cameras > 0) {
      jobs.clear();
      for (int i = 0; i < o.cameras; ++i) jobs.emplace_back(i, o.out + "_" + std::to_string(i) + ".svct");
    }
    // Each camera on its own thread, each table written as soon as it is done: the demo's
    // Segmentations wait for their files.
    auto calibrate = [&scenario](int camera, const std::string& out) {
      const sv::ColorTable table = sv::calibrateSyntheticCamera(scenario, camera);
      const std::string temporary = out + ".partial";
      table.save(temporary);
      if (std::rename(temporary.c_str(), out.c_str()) != 0)
        throw std::runtime_error("cannot rename " + temporary + " to " + out);
      return static_cast<int>(table.statistics().overlap_cells);
    };
    std::vector<std::future<int>> done;
    for (const auto& [camera, out] : jobs)
      done.push_back(std::async(std::launch::async, calibrate, camera, out));
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      const int overlap = done[i].get();
      std::printf(
          "colour table of synthetic camera %d (%s, %dx%d) written to %s: %d overlap cells decided by "
          "Bayes\n",
          jobs[i].first, scenario.name.empty() ? "embedded default" : scenario.name.c_str(), scenario.width,
          scenario.height, jobs[i].second.c_str(), overlap);
    }
    if (o.remove_on_exit) {
      std::fflush(stdout);
      int signal = 0;
      sigwait(&ending, &signal);
      for (const auto& job : jobs) std::remove(job.second.c_str());
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "calibrate_synthetic: " << e.what() << "\n";
    return 2;
  }
}
