// bench_pipeline: the processing latency of the whole vision pipeline per frame — what
// one nodelet manager does between receiving an image and publishing the robots, less the
// pointer passing between nodelets: segmentation (with the search windows fed back) ->
// identification -> tracking -> the next frame's windows (VisionPipeline, the loop the
// offline evaluation runs). A benchmark, not a test.
//
//   rosrun soccer_vision bench_pipeline [--scenario NAME|FILE.yaml] [--frames N] [--cameras C]
//       [--width W --height H] [--cold] [--repeat R] [--ssl] [--sweep true|false]
//       [--ball-streaks true|false] [--json FILE]
//
// Frames of synthetic camera 0 (--cameras C: cameras 0..C-1 of the scenario's layout) are
// rendered first (not timed), with the scenario's pattern and a colour table calibrated like
// the demo's, per camera; then each frame is processed in order on one thread (with C
// cameras, frame i of every camera before frame i + 1, each a millisecond after the previous
// camera's). `load` is the processing time per second of the scenario's video over all
// cameras, in cores: what the cameras at the scenario's frame rate ask of the machine. Before it is
// processed, each frame is written into the delivery buffer (not timed), as the CameraDriver nodelet's source
// writes each image into the message it then publishes: the pipeline meets the frame where the driver's write
// left it (the caches), as in the nodelet manager. --cold processes the rendered frames where they are
// instead: 300 frames of 4 MB are far out of the caches, as a frame a camera's DMA wrote to memory.
// --repeat R runs the frames R times, each time with a fresh pipeline, and takes per frame
// and stage the fastest pass: the work without the interference of a shared machine (on
// ours a single pass's p99 varies by up to 2x from run to run); each pass's p99 is
// printed too. Prints p50 / p99 / max of the total and of each stage (Table II's:
// illumination, pixel classification, recognition and pose, tracking), the share of frames
// searched in windows, and the robots found per frame. --ssl also turns each frame's detections
// and tracker output into the league's detection and tracked packets and sends them to a socket
// of this process on 127.0.0.1 (SslOutput's work, docs/ssl.md): stage `ssl`, and `to_udp_sent`
// = total + ssl, the processing from the image to the tracked packet handed to the kernel.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <nlohmann/json.hpp>
#include <sys/socket.h>

#include "soccer_vision/common/statistics.h"
#include "soccer_vision/pipeline/vision_pipeline.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"
#include "soccer_vision/simulation/synthetic_calibration.h"
#include "soccer_vision/ssl/detection_packet.h"
#include "soccer_vision/ssl/kicked_ball.h"
#include "soccer_vision/ssl/tracked_packet.h"
#include "soccer_vision/ssl/udp_sender.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;
using Clock = std::chrono::steady_clock;

namespace {

struct Options {
  std::string scenario_path;
  int frames = 300, width = 0, height = 0, cameras = 1;
  std::string json;
  bool cold = false;
  int repeat = 1;
  bool ssl = false;
  bool sweep = true;
  bool ball_streaks = true;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--scenario", o.scenario_path,
                 "scenario preset: a name or a YAML file (default: the embedded one)");
  app.add_option("--frames", o.frames, "frames per pass")
      ->check(CLI::Range(10, 1000000))
      ->capture_default_str();
  app.add_option("--cameras", o.cameras, "cameras 0..C-1 of the scenario's layout, processed together")
      ->check(CLI::Range(1, sv::kMaxCameras))
      ->capture_default_str();
  app.add_option("--width", o.width, "[px] image width; 0: the scenario's")->check(CLI::Range(0, 16384));
  app.add_option("--height", o.height, "[px] image height; 0: the scenario's")->check(CLI::Range(0, 16384));
  app.add_option("--json", o.json, "write the figures as JSON");
  app.add_flag("--cold", o.cold, "process frames straight from memory");
  app.add_option("--repeat", o.repeat, "passes, each with a fresh pipeline; per frame the fastest counts")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--sweep", o.sweep,
                 "the periodic global search as a sweep of stripes (false: the whole frame every 30 frames)")
      ->capture_default_str();
  app.add_option("--ball-streaks", o.ball_streaks,
                 "the ball's streak table in its window (false: the colour table there too)")
      ->capture_default_str();
  app.add_flag("--ssl", o.ssl,
               "also build each frame's SSL detection and tracked packets and send them to 127.0.0.1");
}

// A preset name is looked up in this source tree's presets; anything else is a path.
std::string presetPath(const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name.find(".yaml") != std::string::npos)
    return name;
  return std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + name + ".yaml";
}

double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// The --ssl packets' destination: a socket of this process on 127.0.0.1, drained between frames.
class LoopbackSink {
 public:
  LoopbackSink() {
    fd_ = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
      throw std::runtime_error("--ssl: no socket on 127.0.0.1");
    }
    port_ = ntohs(a.sin_port);
  }
  ~LoopbackSink() { close(fd_); }
  int port() const { return port_; }
  void drain() {
    char buffer[65536];
    while (recv(fd_, buffer, sizeof buffer, MSG_DONTWAIT) > 0) {
    }
  }

 private:
  int fd_ = -1;
  int port_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"bench_pipeline: the whole pipeline's processing latency per frame (docs/performance.md)",
               "bench_pipeline"};
  addOptions(app, o);
  if (const auto status = sv::parseCommandLine(app, argc, argv)) return *status;
  try {
    const std::string path = presetPath(o.scenario_path);
    sv::ScenarioConfig scenario = path.empty() ? sv::ScenarioConfig{} : sv::loadScenario(path);
    if (o.width > 0) scenario.width = o.width;
    if (o.height > 0) scenario.height = o.height;
    const sv::FieldGeometry field = sv::fieldGeometryByName(scenario.field);
    const sv::PatternSet patterns = sv::patternSetByName(scenario.pattern);
    if (o.cameras > scenario.cameras)
      throw std::invalid_argument("--cameras " + std::to_string(o.cameras) + ": the scenario has " +
                                  std::to_string(scenario.cameras));
    const auto layout = scenario.sensor.bayer.empty()
                            ? sv::PixelLayout::Bgr
                            : *sv::pixelLayoutForEncoding("bayer_" + scenario.sensor.bayer + "8");
    std::vector<sv::PipelineCamera> cameras;
    std::vector<std::unique_ptr<sv::FieldRenderer>> renderers;
    for (int c = 0; c < o.cameras; ++c) {
      sv::PipelineCamera pc;
      pc.id = c;
      pc.model = sv::scenarioCamera(field, c, scenario);
      pc.segmentation = sv::SegmentationModel::fromTable(
          std::make_shared<const sv::ColorTable>(sv::calibrateSyntheticCamera(scenario, c)));
      pc.layout = layout;
      renderers.push_back(std::make_unique<sv::FieldRenderer>(pc.model, field, patterns, scenario));
      cameras.push_back(pc);
    }

    // frames[i * C + c]: frame i of camera c.
    sv::GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
    std::vector<cv::Mat> frames;
    for (int i = 0; i < o.frames; ++i) {
      for (const auto& renderer : renderers) {
        sv::RenderedFrame f;
        renderer->render(sim.state(), i, f);
        frames.push_back(f.image.clone());
      }
      sim.step(1.0 / scenario.fps);
    }
    const int processed_frames = o.frames * o.cameras;

    // The nodelets' loop in one process (vision_pipeline.h), timed per stage; `repeat`
    // passes over the same frames, each with a fresh pipeline (the same work: the pipeline
    // is deterministic), and per frame and stage the fastest of them.
    const double interval = 1.0 / scenario.fps;
    std::vector<std::string> stages = {"preprocessing", "classification", "recognition", "tracking", "total"};
    if (o.ssl) stages.insert(stages.end(), {"ssl", "to_udp_sent"});
    std::optional<LoopbackSink> sink;
    std::optional<sv::ssl::UdpSender> sender;
    if (o.ssl) {
      sink.emplace();
      sender.emplace("127.0.0.1", sink->port());
    }
    sv::ssl::TrackedPacketOptions tracked_options;
    tracked_options.uuid = sv::ssl::randomUuid();
    std::map<std::string, std::vector<double>> t;
    for (const std::string& stage : stages)
      t[stage].assign(static_cast<std::size_t>(processed_frames), 1e300);
    std::vector<double> pass_p99;
    std::size_t windowed = 0, robots = 0;
    cv::Mat delivered;
    for (int pass = 0; pass < o.repeat; ++pass) {
      sv::VisionPipelineParams params;
      params.search.sweep = o.sweep;
      params.segmentation.ball_streaks = o.ball_streaks;
      sv::VisionPipeline pipeline(cameras, patterns, field, params);
      sv::ssl::KickedBallEstimator kicks;
      std::vector<double> totals;
      windowed = robots = 0;
      for (int i = 0; i < processed_frames; ++i) {
        const int camera = i % o.cameras;
        const cv::Mat* image = &frames[i];
        if (!o.cold) {
          delivered.create(frames[i].size(), frames[i].type());
          frames[i].copyTo(delivered);
          image = &delivered;
        }
        const auto t0 = Clock::now();
        const sv::PipelineFrame f =
            pipeline.process(camera, *image, (i / o.cameras) * interval + 1e-3 * camera);
        const double total = ms(t0, Clock::now());
        double ssl_ms = 0;
        if (sender) {
          // SslOutput's work per frame: one detection packet and one tracked packet, sent.
          const auto s0 = Clock::now();
          const auto& kick = kicks.update(f.output);
          const bool sent =
              sender->send(sv::ssl::detectionPacket(f.detections, static_cast<std::uint32_t>(i), f.stamp)
                               .SerializeAsString()) &&
              sender->send(
                  sv::ssl::trackedPacket(f.output, static_cast<std::uint32_t>(i), kick, tracked_options)
                      .SerializeAsString());
          ssl_ms = ms(s0, Clock::now());
          if (!sent) throw std::runtime_error("--ssl: " + sender->lastError());
          sink->drain();
        }
        windowed += !f.global_search;
        robots += f.output.robots.size();
        const double times[] = {f.times.preprocessing,
                                f.times.classification,
                                f.times.recognition,
                                f.times.tracking,
                                total,
                                ssl_ms,
                                total + ssl_ms};
        for (std::size_t k = 0; k < stages.size(); ++k) {
          double& best = t[stages[k]][static_cast<std::size_t>(i)];
          best = std::min(best, times[k]);
        }
        totals.push_back(total);
      }
      pass_p99.push_back(sv::percentile(totals, 99));
    }

    double busy_ms = 0;
    for (double v : t["total"]) busy_ms += v;
    const double load = busy_ms / 1e3 / (o.frames * interval);  // cores at the scenario's frame rate
    std::printf(
        "bench_pipeline: %s, %d camera(s) of %dx%d %s at %.0f Hz, %d frames each (%s), %.1f %% searched in "
        "windows, %.1f robots tracked per frame; load %.2f cores\n",
        scenario.name.empty() ? "embedded default" : scenario.name.c_str(), o.cameras, scenario.width,
        scenario.height,
        scenario.sensor.bayer.empty() ? "bgr8" : ("bayer_" + scenario.sensor.bayer + "8").c_str(),
        scenario.fps, o.frames, o.cold ? "cold: from memory" : "as the driver writes them",
        100.0 * windowed / processed_frames, static_cast<double>(robots) / processed_frames, load);
    nlohmann::json json = {{"width", scenario.width},
                           {"height", scenario.height},
                           {"cameras", o.cameras},
                           {"fps", scenario.fps},
                           {"frames", o.frames},
                           {"load_cores", load},
                           {"windowed_fraction", static_cast<double>(windowed) / processed_frames},
                           {"cold", o.cold}};
    if (o.repeat > 1) {
      std::printf("  %d passes, per frame the fastest; total p99 of each pass:", o.repeat);
      for (double p : pass_p99) std::printf(" %.3f", p);
      std::printf(" ms\n");
      json["repeat"] = o.repeat;
      json["pass_total_p99_ms"] = pass_p99;
    }
    for (const std::string& stage : stages) {
      const auto& v = t[stage];
      std::printf("  %-15s p50 %7.3f ms   p99 %7.3f ms   max %7.3f ms\n", stage.c_str(),
                  sv::percentile(v, 50), sv::percentile(v, 99), *std::max_element(v.begin(), v.end()));
      json[stage] = {{"p50_ms", sv::percentile(v, 50)},
                     {"p99_ms", sv::percentile(v, 99)},
                     {"max_ms", *std::max_element(v.begin(), v.end())}};
    }
    if (!o.json.empty()) {
      std::ofstream(o.json) << json.dump(2) << "\n";
      std::printf("wrote %s\n", o.json.c_str());
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bench_pipeline: " << e.what() << "\n";
    return 2;
  }
}
