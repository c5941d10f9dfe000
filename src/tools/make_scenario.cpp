// make_scenario: renders a scenario preset into a rosbag (image_raw, camera_info and the
// ground-truth topics of each camera, with capture stamps) and writes the exchange files
// (docs/formats.md) next to it: truth.jsonl, samples.yaml (colour samples on the
// calibration frame, calibration_frame.png), field_points.yaml, plus camera_info.yaml and
// first_frame.png for calibration,
// and samples_camera_<n>_frame_<i>.yaml for the frames a table is calibrated on (as
// calibrate_synthetic: 24 frames 0.375 s apart, those within the recording; polygons where
// the frame shows the objects, i.e. mid-exposure for a blurred frame).
//
//   rosrun soccer_vision make_scenario --preset NAME|FILE.yaml --frames N --out FILE.bag
//       [--cameras 0[,1,...]] [--width W --height H] [--seed S] [--start STAMP]
//       [--compression lz4|bz2|none] [--sample-inset PX] [--click-noise PX]
//       [--calibration-frame auto|N]
//
// --sample-inset PX: the calibration frame's marker and ball polygons (samples.yaml) PX
// pixels inside their outlines where the frame shows them, as a user draws them; --click-noise PX:
// field_points.yaml moved by Gaussian noise of PX pixels per axis, as a user clicks; --calibration-frame
// auto|N: the frame samples.yaml and calibration_frame.png show (default 0; auto: the first
// frame showing every marker colour (robots, ball) the camera shows in the recording, as a user picks
// one, else the first showing the most of them, and the colours it lacks sampled on the
// first frames showing them, as a user samples them on a second frame, in more_samples_<k>.yaml;
// printed as "camera <n>: calibration frame: <i>" and "camera <n>: more samples: frame <j>
// (<colours>) in <file>"). The held-out protocol of docs/evaluation.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <camera_calibration_parsers/parse.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>

#include "soccer_vision/common/bayer_encoding.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/package_paths.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"
#include "soccer_vision/simulation/synthetic_calibration.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;

namespace {

struct Options {
  std::string preset;
  int frames = 0;
  std::string out;
  std::vector<int> cameras = {0};
  int width = 0, height = 0;
  long long seed = -1;
  double start = 1700000000.0;
  std::string compression = "lz4";
  double sample_inset = 0, click_noise = 0;  // px
  std::string calibration_frame = "0";       // "auto" or a frame index
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--preset", o.preset, "scenario preset: a name of config/scenarios/ or a YAML file")
      ->required();
  // An hour at 60 Hz is far more than any test needs; more only fills the disk.
  app.add_option("--frames", o.frames, "frames to render")->required()->check(CLI::Range(1, 216000));
  app.add_option("--out", o.out, "the bag to write; the exchange files go beside it")->required();
  app.add_option("--cameras", o.cameras,
                 "synthetic cameras to record, of the preset's layout (its `cameras`)")
      ->delimiter(',')
      ->check(CLI::Range(0, sv::kMaxCameras - 1))
      ->capture_default_str();
  app.add_option("--width", o.width, "[px] image width; 0: the preset's")->check(CLI::Range(0, 16384));
  app.add_option("--height", o.height, "[px] image height; 0: the preset's")->check(CLI::Range(0, 16384));
  app.add_option("--seed", o.seed, "random seed of the game (default: the preset's)");
  app.add_option("--start", o.start, "[s] capture stamp of frame 0")->capture_default_str();
  app.add_option("--compression", o.compression, "bag chunk compression")
      ->check(CLI::IsMember(std::vector<std::string>{"lz4", "bz2", "none"}))
      ->capture_default_str();
  app.add_option("--sample-inset", o.sample_inset, "[px] sample polygons drawn this far inside each marker")
      ->check(CLI::Range(0.0, 20.0));
  app.add_option("--click-noise", o.click_noise, "[px] random error of each clicked field point")
      ->check(CLI::Range(0.0, 20.0));
  app.add_option("--calibration-frame", o.calibration_frame,
                 "frame of samples.yaml and calibration_frame.png: an index, or auto (the first frame "
                 "showing every marker colour (robots and ball) the camera shows during the recording)")
      ->check(CLI::IsMember(std::vector<std::string>{"auto"}) | CLI::NonNegativeNumber)
      ->capture_default_str();
}

// The marker colours of the robots and balls this camera shows in a scene.
void addMarkerColorsInView(const sv::SceneState& scene, const sv::FieldRenderer& renderer,
                           const sv::PatternSet& patterns, std::set<sv::ColorClass>& colors) {
  for (const auto& r : scene.robots) {
    if (!renderer.robotVisible(r)) continue;
    for (const auto& m : patterns.markers(r.team, r.id)) colors.insert(m.color);
  }
  for (const auto& b : scene.balls) {
    if (renderer.ballVisible(b, scene.robots)) colors.insert(sv::ColorClass::Orange);
  }
}

// How many of `colors` the samples have polygons for.
std::size_t colorsShown(const sv::ColorSamples& samples, const std::set<sv::ColorClass>& colors) {
  return std::count_if(colors.begin(), colors.end(), [&](sv::ColorClass c) {
    const auto it = samples.find(c);
    return it != samples.end() && !it->second.empty();
  });
}

// Where no frame shows every colour, the frames a user samples the missing ones on (the
// calibration UI's second frame): again and again the first frame showing the most of the
// colours still missing, with its polygons of those and of the carpet (a ball's mixture
// with the carpet is modelled on its own frame's carpet).
std::vector<std::pair<int, sv::ColorSamples>> moreSamples(const std::map<int, sv::ColorSamples>& drawn,
                                                          std::set<sv::ColorClass> missing) {
  std::vector<std::pair<int, sv::ColorSamples>> more;
  while (!missing.empty()) {
    int best = -1;
    std::size_t best_shown = 0;
    for (const auto& [frame, samples] : drawn) {
      const std::size_t shown = colorsShown(samples, missing);
      if (shown > best_shown) best_shown = shown, best = frame;
    }
    if (best < 0) break;  // the rest is never shown whole
    const sv::ColorSamples& samples = drawn.at(best);
    sv::ColorSamples picked;
    for (const auto& [color, polygons] : samples) {
      if ((missing.count(color) || color == sv::ColorClass::Carpet) && !polygons.empty())
        picked[color] = polygons;
    }
    for (const auto& entry : picked) missing.erase(entry.first);
    more.emplace_back(best, std::move(picked));
  }
  return more;
}

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// Camera-specific files: plain name for the first camera, "_camera_<n>" for every camera.
std::vector<std::string> cameraFileNames(const std::string& dir, const std::string& stem,
                                         const std::string& ext, int camera, bool first) {
  std::vector<std::string> names = {dir + "/" + stem + "_camera_" + std::to_string(camera) + ext};
  if (first) names.push_back(dir + "/" + stem + ext);
  return names;
}

struct CameraChannel {
  int id;
  std::string ns;
  std::unique_ptr<sv::FieldRenderer> renderer;
  sensor_msgs::CameraInfo info;
  // The user's calibration frame. With "auto": the marker colours the camera shows during
  // the recording, and the earliest frame showing the most of them so far.
  bool calibration_written = false;
  std::set<sv::ColorClass> colors_in_view;
  std::size_t best_shown = 0;
  int best_frame = -1;
  sv::ColorSamples best_samples;
  cv::Mat best_bgr;
  std::map<int, sv::ColorSamples> drawn;  // every frame's, until the calibration frame is chosen
};

// The bag being written. A failed write (a full disk) throws; rosbag::Bag's destructor
// would then close the file, write its index, throw again while the first exception
// unwinds, and abort the process. So while an exception leaves this scope the Bag is let
// go without its destructor (the process ends with the error), else destroyed as usual.
class OutputBag {
 public:
  explicit OutputBag(const std::string& path)
      : bag_(std::make_unique<rosbag::Bag>(path, rosbag::bagmode::Write)),
        exceptions_(std::uncaught_exceptions()) {}
  ~OutputBag() {
    if (std::uncaught_exceptions() > exceptions_) static_cast<void>(bag_.release());
  }
  OutputBag(const OutputBag&) = delete;
  OutputBag& operator=(const OutputBag&) = delete;
  rosbag::Bag& bag() { return *bag_; }

 private:
  std::unique_ptr<rosbag::Bag> bag_;
  int exceptions_;
};

int run(const Options& o) {
  if (o.calibration_frame != "auto") {
    const double n = std::stod(o.calibration_frame);
    if (n != std::floor(n) || n >= o.frames)
      throw std::invalid_argument("--calibration-frame must be auto or a frame index below --frames (" +
                                  std::to_string(o.frames) + "), got " + o.calibration_frame);
  }
  sv::ScenarioConfig scenario = sv::loadScenario(sv::resolveScenarioPath(o.preset));
  if (o.width != 0) scenario.width = o.width;
  if (o.height != 0) scenario.height = o.height;
  sv::checkScenario(scenario, o.preset + " with --width/--height");
  if (o.seed >= 0) scenario.seed = static_cast<std::uint64_t>(o.seed);
  const sv::FieldGeometry field = sv::fieldGeometryByName(scenario.field);
  const sv::PatternSet patterns = sv::patternSetByName(scenario.pattern);
  sv::GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());

  std::vector<CameraChannel> channels;
  for (int id : o.cameras) {
    const auto camera = sv::scenarioCamera(field, id, scenario);
    const std::string frame = "camera_" + std::to_string(id) + "_optical";
    channels.push_back({id,
                        "/camera_" + std::to_string(id),
                        std::make_unique<sv::FieldRenderer>(camera, field, patterns, scenario),
                        sv::toCameraInfo(camera, frame),
                        false,
                        {},
                        0,
                        -1,
                        {},
                        {},
                        {}});
  }
  if (o.calibration_frame == "auto") {
    // The game once through without rendering (deterministic for the seed): which colours
    // each camera will show, so the calibration frame can be one that shows them all.
    sv::GameSimulator preview(scenario, field, patterns.maxRobotsPerTeam());
    for (int i = 0; i < o.frames; ++i) {
      for (auto& ch : channels)
        addMarkerColorsInView(preview.state(), *ch.renderer, patterns, ch.colors_in_view);
      preview.step(1.0 / scenario.fps);
    }
  }

  OutputBag output(o.out);
  rosbag::Bag& bag = output.bag();
  bag.setCompression(o.compression == "lz4"   ? rosbag::compression::LZ4
                     : o.compression == "bz2" ? rosbag::compression::BZ2
                                              : rosbag::compression::Uncompressed);
  const std::string dir = directoryOf(o.out);
  std::vector<sv::FrameRecord> truth;
  const double dt = 1.0 / scenario.fps;
  const int calibration_spacing =
      std::max(1, static_cast<int>(std::lround(sv::SyntheticCalibration{}.seconds_between * scenario.fps)));

  for (int i = 0; i < o.frames; ++i) {
    const sv::SceneState& scene = sim.state();
    const ros::Time stamp(o.start + i * dt);
    sv::FrameRecord record;
    for (auto& ch : channels) {
      const std::string frame_id = ch.info.header.frame_id;
      sensor_msgs::Image img;
      img.header.stamp = stamp;
      img.header.frame_id = frame_id;
      img.header.seq = i;
      img.width = scenario.width;
      img.height = scenario.height;
      img.encoding = ch.renderer->encoding();
      const bool bayer = img.encoding.rfind("bayer", 0) == 0;
      img.step = scenario.width * (bayer ? 1 : 3);
      img.data.resize(static_cast<std::size_t>(img.step) * img.height);
      sv::RenderedFrame rendered;
      rendered.image = cv::Mat(img.height, img.width, bayer ? CV_8UC1 : CV_8UC3, img.data.data(), img.step);
      ch.renderer->render(scene, i, rendered);

      sensor_msgs::CameraInfo info = ch.info;
      info.header = img.header;
      const auto robots = sv::toRobotPoseArray(
          scene, stamp, ch.id, [&](const sv::RobotState& r) { return ch.renderer->robotVisible(r); });
      const auto balls = sv::toBallPoseArray(scene, stamp, ch.id, [&](const sv::BallState& b) {
        return ch.renderer->ballVisible(b, scene.robots);
      });
      bag.write(ch.ns + "/image_raw", stamp, img);
      bag.write(ch.ns + "/camera_info", stamp, info);
      bag.write(ch.ns + "/ground_truth/robots", stamp, robots);
      bag.write(ch.ns + "/ground_truth/balls", stamp, balls);
      if (!balls.balls.empty()) bag.write(ch.ns + "/ground_truth/ball", stamp, balls.balls.front());

      // One truth record per instant: an object is visible if any camera sees it.
      const auto merged = sv::toFrameRecord(robots, balls);
      if (record.robots.empty() && record.balls.empty()) {
        record = merged;
      } else {
        for (std::size_t k = 0; k < record.robots.size(); ++k) {
          record.robots[k].visible = *record.robots[k].visible || *merged.robots[k].visible;
        }
        for (std::size_t k = 0; k < record.balls.size(); ++k) {
          record.balls[k].visible = *record.balls[k].visible || *merged.balls[k].visible;
        }
      }
      record.stamp = stamp.toSec();

      // Where the frame shows the objects (mid-exposure when blurred): polygons are drawn there,
      // by calibrate_synthetic and by a user alike.
      const sv::SceneState shown = sv::extrapolate(scene, sv::shownTimeAfterStamp(scenario.sensor));
      // Colour samples of the calibration frames, as calibrate_synthetic picks them: one
      // frame shows only the robots in view, so a table needs several.
      if (i % calibration_spacing == 0 && i / calibration_spacing < sv::SyntheticCalibration{}.frames) {
        const auto samples = ch.renderer->paintedSamples(shown);
        sv::writeTextFile(
            dir + "/samples_camera_" + std::to_string(ch.id) + "_frame_" + std::to_string(i) + ".yaml",
            sv::toYaml(samples));
      }
      const bool first = &ch == &channels.front();
      if (!ch.calibration_written) {
        // The frame a user calibrates the colours on: polygons as drawn on it.
        const sv::SampleOptions drawn = sv::SampleOptions::drawnByUser(o.sample_inset);
        sv::ColorSamples samples = ch.renderer->paintedSamples(shown, drawn);
        cv::Mat bgr = sv::bgrOfEncoding(rendered.image, img.encoding);
        const bool automatic = o.calibration_frame == "auto";
        if (automatic) {
          const std::size_t shown = colorsShown(samples, ch.colors_in_view);
          ch.drawn[i] = samples;
          if (ch.best_frame < 0 || shown > ch.best_shown) {
            ch.best_shown = shown;
            ch.best_frame = i;
            ch.best_samples = samples;
            ch.best_bgr = bgr.clone();
          }
        }
        const bool all_shown = automatic && ch.best_shown == ch.colors_in_view.size();
        if (automatic ? all_shown || i == o.frames - 1 : i == std::stoi(o.calibration_frame)) {
          const int chosen = automatic ? ch.best_frame : i;
          if (automatic) {
            samples = ch.best_samples;
            bgr = ch.best_bgr;
          }
          for (const auto& f : cameraFileNames(dir, "samples", ".yaml", ch.id, first))
            sv::writeTextFile(f, sv::toYaml(samples));
          for (const auto& f : cameraFileNames(dir, "calibration_frame", ".png", ch.id, first)) {
            if (!cv::imwrite(f, bgr)) throw std::runtime_error(f + ": cannot write image");
          }
          std::printf("camera %d: calibration frame: %d", ch.id, chosen);
          if (automatic)
            std::printf(" (shows %zu of the %zu marker colours in view)", ch.best_shown,
                        ch.colors_in_view.size());
          std::printf("\n");
          if (automatic && !all_shown) {
            std::set<sv::ColorClass> missing;
            for (const sv::ColorClass c : ch.colors_in_view) {
              if (!colorsShown(samples, {c})) missing.insert(c);
            }
            int k = 0;
            for (const auto& [frame, more] : moreSamples(ch.drawn, missing)) {
              const auto files =
                  cameraFileNames(dir, "more_samples_" + std::to_string(++k), ".yaml", ch.id, first);
              for (const auto& f : files) sv::writeTextFile(f, sv::toYaml(more));
              std::printf("camera %d: more samples: frame %d (%s) in %s\n", ch.id, frame,
                          sv::sampledClassNames(more).c_str(), files.front().c_str());
            }
          }
          ch.drawn.clear();
          ch.calibration_written = true;
          ch.best_samples.clear();
          ch.best_bgr.release();
        }
      }
      if (i == 0) {
        auto points = sv::fieldCorrespondences(ch.renderer->camera(), field);
        if (o.click_noise > 0) sv::addClickNoise(points, o.click_noise, scenario.seed + 31 * ch.id);
        const cv::Mat bgr = sv::bgrOfEncoding(rendered.image, img.encoding);
        for (const auto& f : cameraFileNames(dir, "field_points", ".yaml", ch.id, first))
          sv::writeTextFile(f, sv::toYaml(points));
        for (const auto& f : cameraFileNames(dir, "first_frame", ".png", ch.id, first)) {
          if (!cv::imwrite(f, bgr)) throw std::runtime_error(f + ": cannot write image");
        }
        for (const auto& f : cameraFileNames(dir, "camera_info", ".yaml", ch.id, first)) {
          if (!camera_calibration_parsers::writeCalibration(f, "camera_" + std::to_string(ch.id), ch.info)) {
            throw std::runtime_error(f + ": cannot write camera_info");
          }
        }
      }
    }
    truth.push_back(record);
    sim.step(dt);
  }
  bag.close();
  sv::writeJsonLines(dir + "/truth.jsonl", truth);

  std::printf(
      "wrote %s: %d frames x %zu camera(s), %dx%d %s, %.0f fps, preset '%s' (%s pattern, %d+%d robots)\n",
      o.out.c_str(), o.frames, channels.size(), scenario.width, scenario.height,
      channels.front().renderer->encoding().c_str(), scenario.fps, scenario.name.c_str(),
      patterns.name.c_str(), scenario.blue_robots, scenario.yellow_robots);
  std::printf(
      "and %s/{truth.jsonl, samples.yaml, calibration_frame.png, field_points.yaml, camera_info.yaml, "
      "first_frame.png, samples_camera_<n>_frame_<i>.yaml, more_samples_<k>.yaml where needed}\n",
      dir.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "make_scenario: renders a scenario preset into a rosbag with its ground truth and the\n"
      "exchange files beside it (docs/tools.md)",
      "make_scenario"};
  addOptions(app, o);
  if (const auto status = sv::parseCommandLine(app, argc, argv)) return *status;
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::cerr << "make_scenario: " << e.what() << "\n";
    return 2;
  }
}
