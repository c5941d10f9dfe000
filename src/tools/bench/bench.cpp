// bench: the segmentation benchmark (a program, not a test). Per resolution (780x580,
// 1280x1024, 2448x2048), on frames of the synthetic camera, in one process and on one
// thread: soccer_vision's segmentation per stage (illumination, classification,
// morphology, regions) and in total, full frame and with search windows, bgr8 and Bayer;
// beside (a) a plain OpenCV pipeline (cvtColor to HSV, inRange per class, morphologyEx
// open + close, connectedComponentsWithStats) on the same frames and (b) a memory-read
// floor (one streaming read of the frame). Prints medians and ratios.
//
//   rosrun soccer_vision bench [--json FILE] [--frames N] [--repeat R] [--morph-kernel K]
//                              [--resolutions 780x580,1280x1024,2448x2048] [--windows-only]
//                              [--regions FILE]
//
// --windows-only runs the windowed segmentation alone (for a profiler: perf record,
// valgrind --tool=callgrind); the other figures are then not measured.
// --regions FILE writes every region found (full frame, windows, Bayer, sharpened; all
// digits) so that two builds can be compared for bit-identical results with diff.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "opencv_baseline.h"
#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
  std::string json;
  int frames = 8;
  int repeat = 5;
  bool windows_only = false;
  std::string regions;
  int morph_kernel = sv::RegionParams{}.morph_kernel;  // another kernel's cost, compared in one session
  std::vector<cv::Size> resolutions = {{780, 580}, {1280, 1024}, {2448, 2048}};
};

void addOptions(CLI::App& app, Options& o, std::vector<std::string>& resolutions) {
  app.add_option("--json", o.json, "write the figures as JSON");
  app.add_option("--frames", o.frames, "frames per resolution")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--repeat", o.repeat, "passes over the frames")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--resolutions", resolutions, "WxH,... (default 780x580,1280x1024,2448x2048)")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& r) -> std::string {
            int w = 0, h = 0;
            char end = 0;
            if (std::sscanf(r.c_str(), "%dx%d%c", &w, &h, &end) != 2 || w < 2 || h < 2 || w > 16384 ||
                h > 16384)
              return "resolution '" + r + "' is not WxH (2..16384 each)";
            return "";
          },
          "WxH", "resolution"));
  app.add_flag("--windows-only", o.windows_only, "run the windowed segmentation alone (for a profiler)");
  app.add_option("--regions", o.regions, "write every region found, all digits (compare builds with diff)");
  app.add_option("--morph-kernel", o.morph_kernel, "the segmentation's opening (RegionParams::morph_kernel)")
      ->check(CLI::Range(0, 15))
      ->capture_default_str();
}

std::vector<cv::Size> parseResolutions(const std::vector<std::string>& texts) {
  std::vector<cv::Size> sizes;
  for (const std::string& r : texts) {
    int w = 0, h = 0;
    std::sscanf(r.c_str(), "%dx%d", &w, &h);  // checked by the option's validator
    sizes.emplace_back(w, h);
  }
  return sizes;
}

template <typename F>
double timeMs(F&& f) {
  const auto t0 = Clock::now();
  f();
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// One streaming read of the frame: the floor any per-pixel method has to pay.
std::uint64_t streamingRead(const cv::Mat& m) {
  std::uint64_t sum = 0;
  for (int y = 0; y < m.rows; ++y) {
    const auto* p = reinterpret_cast<const std::uint64_t*>(m.ptr(y));
    const std::size_t n = m.cols * m.elemSize() / sizeof(std::uint64_t);
    for (std::size_t i = 0; i < n; ++i) sum += p[i];
  }
  return sum;
}

// Search windows of side R around every robot and ball the camera sees, like tracking
// will feed back: R = 200 px at 1280 px width, scaled with the width.
std::vector<cv::Rect> windowsFor(const sv::SceneState& scene, const sv::FieldRenderer& renderer,
                                 const sv::PatternSet& patterns) {
  const auto& cam = renderer.camera();
  const int side = static_cast<int>(std::lround(200.0 * cam.width() / 1280.0));
  std::vector<cv::Rect> out;
  auto add = [&](const Eigen::Vector3d& p) {
    const auto px = cam.projectInImage(p);
    if (px)
      out.emplace_back(static_cast<int>(px->x()) - side / 2, static_cast<int>(px->y()) - side / 2, side,
                       side);
  };
  for (const auto& r : scene.robots) add({r.x, r.y, patterns.height(r.team)});
  for (const auto& b : scene.balls) add({b.x, b.y, b.z});
  return out;
}

// One line per region, every digit: identical files mean identical results.
void writeRegions(std::FILE* out, const std::string& what, const sv::SegmentationResult& result) {
  if (!out) return;
  for (const sv::Region& r : result.regions) {
    std::fprintf(out, "%s c%d a%u %.17g %.17g %.17g %.17g %.17g %.17g box %d %d %d %d\n", what.c_str(),
                 static_cast<int>(r.color), r.area, r.cx, r.cy, r.mu20, r.mu11, r.mu02, r.orientation,
                 r.bbox.x, r.bbox.y, r.bbox.width, r.bbox.height);
  }
}

struct Series {
  std::map<std::string, std::vector<double>> ms;
  void add(const std::string& key, double v) { ms[key].push_back(v); }
  double med(const std::string& key) const {
    const auto it = ms.find(key);
    return it == ms.end() ? 0 : sv::percentile(it->second, 50);
  }
};

nlohmann::json runResolution(const cv::Size& size, const Options& o, std::FILE* regions_out) {
  sv::ScenarioConfig scenario;
  scenario.width = size.width;
  scenario.height = size.height;
  // Every robot (5 + 5) and the ball play in camera 0's half, so that each frame shows the
  // whole game: 11 search windows, the worst case of one camera.
  scenario.motion.area_x_min = -4.3;
  scenario.motion.area_x_max = -0.4;
  sv::ScenarioConfig bayer_scenario = scenario;
  bayer_scenario.sensor.bayer = "rggb";
  const sv::FieldGeometry field = sv::fieldGeometryByName(scenario.field);
  const sv::PatternSet patterns = sv::patternSetByName(scenario.pattern);
  const auto camera = sv::CameraModel::defaultCamera(field, 0, size.width, size.height);
  const sv::FieldRenderer renderer(camera, field, patterns, scenario);
  const sv::FieldRenderer bayer_renderer(camera, field, patterns, bayer_scenario);
  sv::GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());

  std::vector<sv::SceneState> scenes;
  std::vector<cv::Mat> bgr, bayer;
  for (int i = 0; i < o.frames; ++i) {
    scenes.push_back(sim.state());
    sv::RenderedFrame f, fb;
    renderer.render(sim.state(), i, f);
    bayer_renderer.render(sim.state(), i, fb);
    bgr.push_back(f.image.clone());
    bayer.push_back(fb.image.clone());
    sim.step(0.25);
  }
  const sv::ColorSamples samples = sv::calibrationSamples(scenes.front(), camera, field, patterns);
  const auto table =
      std::make_shared<const sv::ColorTable>(sv::calibrateColorTable({{bgr.front(), samples}}));
  std::shared_ptr<const sv::SegmentationModel> model;
  const double model_ms = timeMs([&] { model = sv::SegmentationModel::fromTable(table); });
  // A Bayer camera is calibrated on its own quads' colours, as its user does (they are not
  // the bgr8 frame's: the quads across a line's edge read yellow or cyan).
  const auto bayer_model = sv::SegmentationModel::fromTable(std::make_shared<const sv::ColorTable>(
      sv::calibrateColorTable({{sv::classifiedColors(bayer.front(), sv::PixelLayout::BayerRggb), samples}})));
  const sv::OpenCvBaseline baseline(*table);

  sv::SegmentationParams params;
  params.regions.morph_kernel = o.morph_kernel;
  sv::Segmenter segmenter(params);
  sv::SegmentationParams sharpening = params;
  sharpening.sharpen = 0.5;
  sv::Segmenter sharpened(sharpening);
  sv::SegmentationResult result;
  Series s;
  std::size_t regions = 0, windows = 0;
  volatile std::uint64_t sink = 0;
  auto tag = [&](int frame, const char* what) {
    return std::to_string(size.width) + "x" + std::to_string(size.height) + " frame " +
           std::to_string(frame) + " " + what;
  };
  for (int i = 0; i < o.frames; ++i) {
    const auto wins = windowsFor(scenes[i], renderer, patterns);
    windows += wins.size();
    for (int r = 0; r < o.repeat; ++r) {
      if (!o.windows_only) {
        segmenter.process(*model, bgr[i], sv::PixelLayout::Bgr, {}, result);
        s.add("total", result.timings.total_ms);
        s.add("illumination", result.timings.illumination_ms);
        s.add("classification", result.timings.classification_ms);
        s.add("morphology", result.timings.morphology_ms);
        s.add("regions", result.timings.regions_ms);
        s.add("grid_points", result.grid_points);
        s.add("classified_pixels", result.classified_pixels);
        regions += result.regions.size();
        if (r == 0) writeRegions(regions_out, tag(i, "full"), result);
      }
      segmenter.process(*model, bgr[i], sv::PixelLayout::Bgr, wins, result);
      s.add("windowed", result.timings.total_ms);
      s.add("windowed_illumination", result.timings.illumination_ms);
      s.add("windowed_classification", result.timings.classification_ms);
      s.add("windowed_morphology", result.timings.morphology_ms);
      s.add("windowed_regions", result.timings.regions_ms);
      s.add("windowed_grid_points", result.grid_points);
      s.add("windowed_classified_pixels", result.classified_pixels);
      if (r == 0) writeRegions(regions_out, tag(i, "windows"), result);
      if (o.windows_only) {
        regions += result.regions.size();
        continue;
      }
      sharpened.process(*model, bgr[i], sv::PixelLayout::Bgr, {}, result);
      s.add("sharpened", result.timings.total_ms);
      if (r == 0) writeRegions(regions_out, tag(i, "sharpened"), result);
      segmenter.process(*bayer_model, bayer[i], sv::PixelLayout::BayerRggb, {}, result);
      s.add("bayer", result.timings.total_ms);
      s.add("bayer_grid_points", result.grid_points);
      s.add("bayer_classified_pixels", result.classified_pixels);
      if (r == 0) writeRegions(regions_out, tag(i, "bayer"), result);
      s.add("opencv", timeMs([&] { sink = sink + baseline.run(bgr[i]); }));
      s.add("floor", timeMs([&] { sink = sink + streamingRead(bgr[i]); }));
    }
  }

  const double seg = s.med("total"), cv_ms = s.med("opencv"), floor = s.med("floor");
  std::printf(
      "\n%dx%d  (%d frames x %d repeats; lookup built in %.0f ms; %.1f regions/frame; %.1f windows/frame)\n",
      size.width, size.height, o.frames, o.repeat, model_ms,
      static_cast<double>(regions) / (o.frames * o.repeat), static_cast<double>(windows) / o.frames);
  if (!o.windows_only) {
    std::printf(
        "  segmentation, full frame   %8.3f ms  (illumination %.3f, classification %.3f, morphology %.3f, "
        "regions %.3f)\n",
        seg, s.med("illumination"), s.med("classification"), s.med("morphology"), s.med("regions"));
  }
  std::printf(
      "  segmentation, windows      %8.3f ms  (illumination %.3f, classification %.3f, morphology %.3f, "
      "regions %.3f)\n",
      s.med("windowed"), s.med("windowed_illumination"), s.med("windowed_classification"),
      s.med("windowed_morphology"), s.med("windowed_regions"));
  if (o.windows_only) {
    return {{"width", size.width}, {"height", size.height}, {"windowed_ms", s.med("windowed")}};
  }
  std::printf(
      "  pixels looked up: full frame %.0f grid + %.0f around hits, windows %.0f grid + %.0f around hits\n",
      s.med("grid_points"), s.med("classified_pixels"), s.med("windowed_grid_points"),
      s.med("windowed_classified_pixels"));
  std::printf("  segmentation, sharpen 0.5  %8.3f ms  (%.2fx unsharpened)\n", s.med("sharpened"),
              s.med("sharpened") / seg);
  std::printf("  segmentation, bayer_rggb8  %8.3f ms  (%.2fx bgr8; %.0f grid + %.0f around hits)\n",
              s.med("bayer"), s.med("bayer") / seg, s.med("bayer_grid_points"),
              s.med("bayer_classified_pixels"));
  std::printf("  OpenCV pipeline            %8.3f ms  -> soccer_vision is %.1fx faster\n", cv_ms,
              cv_ms / seg);
  std::printf("  memory-read floor          %8.3f ms  -> soccer_vision is %.2fx the floor\n", floor,
              seg / floor);

  return {{"width", size.width},
          {"height", size.height},
          {"segmentation_ms", seg},
          {"windowed_ms", s.med("windowed")},
          {"sharpened_ms", s.med("sharpened")},
          {"bayer_ms", s.med("bayer")},
          {"opencv_baseline_ms", cv_ms},
          {"memory_floor_ms", floor},
          {"stages_ms",
           {{"illumination", s.med("illumination")},
            {"classification", s.med("classification")},
            {"morphology", s.med("morphology")},
            {"regions", s.med("regions")}}},
          {"speedup_vs_opencv", cv_ms / seg},
          {"ratio_to_memory_floor", seg / floor},
          {"lookup_build_ms", model_ms}};
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::vector<std::string> resolutions;
  CLI::App app{"bench: the segmentation benchmark (docs/performance.md)", "bench"};
  addOptions(app, o, resolutions);
  if (const auto status = sv::parseCommandLine(app, argc, argv)) return *status;
  if (!resolutions.empty()) o.resolutions = parseResolutions(resolutions);
  try {
    cv::setNumThreads(1);  // one thread for everyone: the comparison is per core
    nlohmann::json report;
    report["threads"] = 1;
    report["frames"] = o.frames;
    report["repeat"] = o.repeat;
    std::FILE* regions_out = nullptr;
    if (!o.regions.empty()) {
      regions_out = std::fopen(o.regions.c_str(), "w");
      if (!regions_out) throw std::runtime_error("cannot write " + o.regions);
    }
    for (const auto& size : o.resolutions) {
      report["resolutions"][std::to_string(size.width) + "x" + std::to_string(size.height)] =
          runResolution(size, o, regions_out);
    }
    if (regions_out) std::fclose(regions_out);
    if (!o.json.empty()) {
      std::ofstream(o.json) << report.dump(2) << "\n";
      std::printf("\nwrote %s\n", o.json.c_str());
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bench: " << e.what() << "\n";
    return 2;
  }
}
