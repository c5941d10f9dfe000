#include "soccer_vision/sources/synthetic_source.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <sstream>

#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"
#include "soccer_vision/sources/source_settings.h"

namespace soccer_vision {

namespace {

double systemNow() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

constexpr double kMaxFps = 1000.0;
constexpr int kMaxSide = 16384;

struct ControlRange {
  const char* name;
  double min, max;
};
constexpr ControlRange kControls[] = {
    {"brightness", 0.0, 10.0},
    {"noise_sigma", 0.0, 100.0},
    {"flicker", 0.0, 1.0},
};

double* controlField(ScenarioConfig& s, const std::string& name) {
  if (name == "brightness") return &s.lighting.brightness;
  if (name == "noise_sigma") return &s.sensor.noise_sigma;
  if (name == "flicker") return &s.lighting.flicker;
  return nullptr;
}

bool checkFps(double fps, std::string& error) {
  if (!(fps > 0.0) || fps > kMaxFps) {
    std::ostringstream os;
    os << "fps " << fps << " out of range (0, " << kMaxFps << "]";
    error = os.str();
    return false;
  }
  return true;
}

}  // namespace

struct SyntheticSource::Pending {
  std::optional<double> fps;
  ScenarioConfig scenario;  // controls applied on top of the current scenario
  bool scenario_changed = false;
};

SyntheticSource::SyntheticSource() : pending_(std::make_unique<Pending>()) {}

SyntheticSource::~SyntheticSource() = default;

OpenResult SyntheticSource::open(const FrameSourceOptions& options) {
  close();
  OpenResult result;

  if (options.fps < 0 || options.width < 0 || options.height < 0) {
    result.error = "fps, width and height must be >= 0 (0 = the scenario's value)";
    return result;
  }

  ScenarioConfig scenario;  // the embedded default
  if (!options.scenario.empty()) {
    try {
      scenario = loadScenario(options.scenario);
    } catch (const std::exception& e) {
      result.warnings.push_back("scenario '" + options.scenario + "' could not be loaded (" + e.what() +
                                "); using the embedded default scenario");
      scenario = ScenarioConfig{};
    }
  }
  if (options.camera_index < 0 || options.camera_index >= scenario.cameras) {
    result.error = "the scenario '" + scenario.name + "' has cameras 0.." +
                   std::to_string(scenario.cameras - 1) + ", not " + std::to_string(options.camera_index);
    return result;
  }
  if (options.fps > 0) scenario.fps = options.fps;
  if (options.width > 0) scenario.width = options.width;
  if (options.height > 0) scenario.height = options.height;
  if (!checkFps(scenario.fps, result.error)) return result;
  if (scenario.width <= 0 || scenario.height <= 0 || scenario.width > kMaxSide ||
      scenario.height > kMaxSide) {
    result.error = "resolution " + std::to_string(scenario.width) + "x" + std::to_string(scenario.height) +
                   " out of range";
    return result;
  }

  try {
    try {
      patterns_ = patternSetByName(scenario.pattern);
    } catch (const std::exception& e) {
      result.warnings.push_back("pattern set '" + scenario.pattern + "' could not be loaded (" + e.what() +
                                "); using the built-in two_tag pattern");
      patterns_ = PatternSet::twoTag();
    }
    field_ = fieldGeometryByName(scenario.field);
    camera_ = scenarioCamera(field_, options.camera_index, scenario);
    sim_ = std::make_unique<GameSimulator>(scenario, field_, patterns_.maxRobotsPerTeam());
    renderer_ = std::make_unique<FieldRenderer>(camera_, field_, patterns_, scenario);
  } catch (const std::exception& e) {
    sim_.reset();
    renderer_.reset();
    result.error = std::string("synthetic scene setup failed: ") + e.what();
    return result;
  }

  format_.width = scenario.width;
  format_.height = scenario.height;
  format_.encoding = renderer_->encoding();
  format_.cv_type = cvTypeForEncoding(format_.encoding);
  if (format_.cv_type < 0) {
    sim_.reset();
    renderer_.reset();
    result.error = "renderer produces unsupported encoding '" + format_.encoding + "'";
    return result;
  }
  format_.step = static_cast<std::size_t>(scenario.width) * CV_ELEM_SIZE(format_.cv_type);

  SettingsReader settings(options.settings);
  const double replay_frames = settings.number("replay_frames", 0);
  const double replay_bytes = replay_frames * static_cast<double>(format_.bytes());
  if (!settings.ok() || !(replay_frames == 0 || replay_frames >= 2) ||
      replay_frames != std::floor(replay_frames) || replay_bytes > static_cast<double>(kMaxReplayBytes)) {
    sim_.reset();
    renderer_.reset();
    result.error = settings.ok()
                       ? "replay_frames must be 0 (off) or a whole number >= 2 whose frames fit in " +
                             std::to_string(kMaxReplayBytes >> 20) + " MiB (" +
                             std::to_string(format_.bytes() >> 20) + " MiB each)"
                       : settings.error();
    return result;
  }
  replay_frames_ = static_cast<std::int64_t>(replay_frames);
  replay_.clear();

  base_stamp_ = options.epoch > 0 ? options.epoch : systemNow();
  base_scene_time_ = 0;
  base_index_ = 0;
  next_n_ = 0;
  sim_n_ = 0;
  started_ = false;
  produced_ = false;
  last_stamp_ = 0;
  last_scene_time_ = 0;

  std::lock_guard<std::mutex> lock(mutex_);
  scenario_ = scenario;
  period_ = 1.0 / scenario.fps;
  pending_ = std::make_unique<Pending>();
  pending_->scenario = scenario;
  dropped_ = 0;
  interrupted_ = false;
  open_ = true;
  result.ok = true;
  return result;
}

void SyntheticSource::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  open_ = false;
  renderer_.reset();
  sim_.reset();
}

bool SyntheticSource::isOpen() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

FrameFormat SyntheticSource::format() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_ ? format_ : FrameFormat{};
}

double SyntheticSource::fps() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return 1.0 / period_;
}

void SyntheticSource::interrupt() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    interrupted_ = true;
  }
  wake_.notify_all();
}

bool SyntheticSource::setFps(double fps, std::string& error) {
  if (!checkFps(fps, error)) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  pending_->fps = fps;
  wake_.notify_all();  // a grab() waiting at the old rate re-plans
  return true;
}

std::vector<std::string> SyntheticSource::controls() const {
  std::vector<std::string> names;
  for (const ControlRange& c : kControls) names.emplace_back(c.name);
  return names;
}

std::optional<double> SyntheticSource::control(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  ScenarioConfig s = pending_->scenario;  // the newest value, applied or not
  const double* field = controlField(s, name);
  if (!field) return std::nullopt;
  return *field;
}

bool SyntheticSource::setControl(const std::string& name, double value, std::string& error) {
  for (const ControlRange& c : kControls) {
    if (name != c.name) continue;
    if (!(value >= c.min && value <= c.max)) {
      std::ostringstream os;
      os << "control '" << name << "' = " << value << " out of range [" << c.min << ", " << c.max << "]";
      error = os.str();
      return false;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    double* field = controlField(pending_->scenario, name);
    if (*field != value) {
      *field = value;
      pending_->scenario_changed = true;
    }
    return true;
  }
  return FrameSource::setControl(name, value, error);
}

std::optional<CameraIntrinsics> SyntheticSource::trueIntrinsics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!open_) return std::nullopt;
  return camera_.intrinsics();
}

std::optional<Eigen::Isometry3d> SyntheticSource::trueFieldTCamera() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!open_) return std::nullopt;
  return camera_.fieldTCamera();
}

ScenarioConfig SyntheticSource::scenario() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return scenario_;
}

CameraModel SyntheticSource::camera() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return camera_;
}

std::uint64_t SyntheticSource::droppedFrames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

bool SyntheticSource::applyPending(std::string& error) {
  std::optional<double> fps;
  std::optional<ScenarioConfig> scenario;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    fps.swap(pending_->fps);
    if (pending_->scenario_changed) {
      pending_->scenario_changed = false;
      scenario = pending_->scenario;
    }
  }
  if (fps && std::abs(*fps * period_ - 1.0) > 1e-12) {
    const double period = 1.0 / *fps;
    if (produced_) {
      // Continue the game from the last frame at the new rate.
      base_index_ += next_n_ - 1;
      base_stamp_ = last_stamp_;
      base_scene_time_ = last_scene_time_;
      next_n_ = 1;
      sim_n_ = 0;
    } else {
      // Nothing shown yet: the first frame is re-planned on the new time grid.
      started_ = false;
    }
    replay_.clear();  // rendered at the old rate
    std::lock_guard<std::mutex> lock(mutex_);
    period_ = period;
    scenario_.fps = *fps;
    pending_->scenario.fps = *fps;
  }
  if (scenario) {
    scenario->fps = 1.0 / period_;
    try {
      auto renderer = std::make_unique<FieldRenderer>(camera_, field_, patterns_, *scenario);
      if (renderer->encoding() != format_.encoding) {
        error = "new settings change the encoding; ignored";
        return false;
      }
      renderer_ = std::move(renderer);
      replay_.clear();  // rendered with the old settings
      std::lock_guard<std::mutex> lock(mutex_);
      scenario_ = *scenario;
    } catch (const std::exception& e) {
      error = std::string("new settings rejected by the renderer: ") + e.what();
      return false;
    }
  }
  return true;
}

bool SyntheticSource::waitUntil(double t) {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!interrupted_ && !pending_->fps) {
    const double remaining = t - systemNow();
    if (remaining <= 0) return true;
    wake_.wait_for(lock, std::chrono::duration<double>(std::min(remaining, 0.1)));
  }
  return !interrupted_;
}

GrabStatus SyntheticSource::grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (interrupted_) return GrabStatus::Interrupted;
    if (!open_) {
      error = "synthetic source is not open";
      return GrabStatus::Error;
    }
  }
  if (image.data == nullptr || image.rows != format_.height || image.cols != format_.width ||
      image.type() != format_.cv_type) {
    error = "grab() needs a " + std::to_string(format_.width) + "x" + std::to_string(format_.height) + " " +
            format_.encoding + " buffer";
    return GrabStatus::Error;
  }

  const double deadline = systemNow() + std::max(0.0, timeout_s);
  double due = 0;
  // Replay: the frame is copied in just before its capture time, as a camera's DMA has it in
  // memory by then without taking the processor from the previous frame's processing;
  // again only if frames are skipped after the wait.
  std::int64_t copied = -1;
  const auto copyReplay = [&](std::int64_t index) {
    if (copied == index) return;
    const double start = systemNow();
    replayPosition(index).frame.image.copyTo(image);  // same size and type: into the caller's buffer
    copied = index;
    replay_lead_ = std::max(0.9 * replay_lead_, 1.5 * (systemNow() - start) + 0.5e-3);
  };
  for (;;) {
    std::string settings_error;
    if (!applyPending(settings_error)) {
      error = settings_error;
      return GrabStatus::Error;
    }
    if (replay_frames_ > 0 && replay_.empty()) {
      // Before the first frame is planned: rendering them is not a camera falling behind.
      if (!renderReplay(error)) return error.empty() ? GrabStatus::Interrupted : GrabStatus::Error;
      copied = -1;  // a frame copied before was of the replaced frames
    }
    if (!started_) {
      // First frame: the first capture time on the grid at or after now.
      const double k = std::ceil((systemNow() - base_stamp_) / period_ - 1e-9);
      next_n_ = std::max<std::int64_t>(0, static_cast<std::int64_t>(k));
      started_ = true;
    }
    due = base_stamp_ + static_cast<double>(next_n_) * period_;
    if (!replay_.empty() && copied != base_index_ + next_n_) {
      if (!waitUntil(std::min(due - replay_lead_, deadline))) return GrabStatus::Interrupted;
      if (systemNow() < due - replay_lead_) return GrabStatus::Timeout;
      copyReplay(base_index_ + next_n_);
    }
    const double wake_at = std::min(due, deadline);
    if (!waitUntil(wake_at)) return GrabStatus::Interrupted;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pending_->fps) continue;  // re-plan at the new rate
    }
    if (systemNow() >= due) break;
    return GrabStatus::Timeout;
  }

  // More than one period late: skip to the newest frame whose capture time has passed.
  const double now = systemNow();
  if (now - due > period_) {
    const auto newest = static_cast<std::int64_t>(std::floor((now - base_stamp_) / period_));
    if (newest > next_n_) {
      if (produced_ || next_n_ > 0) {
        std::lock_guard<std::mutex> lock(mutex_);
        dropped_ += static_cast<std::uint64_t>(newest - next_n_);
      }
      next_n_ = newest;
      due = base_stamp_ + static_cast<double>(next_n_) * period_;
    }
  }

  const std::int64_t index = base_index_ + next_n_;
  SceneState scene;
  if (!replay_.empty()) {
    copyReplay(index);
    const ReplayPosition at = replayPosition(index);
    const ReplayFrame& frame = at.frame;
    info.encoding = frame.encoding;
    scene = frame.scene;
    if (at.backwards) {
      for (RobotState& r : scene.robots) r.vx = -r.vx, r.vy = -r.vy, r.omega = -r.omega;
      for (BallState& b : scene.balls) b.vx = -b.vx, b.vy = -b.vy, b.vz = -b.vz;
    }
    info.robot_visible = frame.robot_visible;
    info.ball_visible = frame.ball_visible;
  } else {
    // Advance the game in whole periods (identical sub-steps for every instance).
    for (std::int64_t i = 0; sim_n_ < next_n_; ++sim_n_, ++i) {
      if ((i & 1023) == 1023) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (interrupted_) return GrabStatus::Interrupted;
      }
      sim_->step(period_);
    }
    scene = sim_->state();
    scene.time = base_scene_time_ + static_cast<double>(next_n_) * period_;
    try {
      renderInto(scene, index, image, info.encoding, info.robot_visible, info.ball_visible);
    } catch (const std::exception& e) {
      error = std::string("rendering failed: ") + e.what();
      return GrabStatus::Error;
    }
  }

  info.stamp = due;
  info.sequence = static_cast<std::uint64_t>(index);
  last_stamp_ = due;
  last_scene_time_ = scene.time;
  info.ground_truth = std::move(scene);
  produced_ = true;
  ++next_n_;
  return GrabStatus::Ok;
}

void SyntheticSource::renderInto(const SceneState& scene, std::int64_t index, cv::Mat& image,
                                 std::string& encoding, std::vector<bool>& robot_visible,
                                 std::vector<bool>& ball_visible) const {
  RenderedFrame out;
  out.image = image;  // shares the buffer
  renderer_->render(scene, index, out);
  if (out.image.data != image.data) out.image.copyTo(image);  // renderer reallocated
  encoding = out.encoding.empty() ? format_.encoding : out.encoding;
  robot_visible.clear();
  for (const RobotState& r : scene.robots) robot_visible.push_back(renderer_->robotVisible(r));
  ball_visible.clear();
  for (const BallState& b : scene.balls) ball_visible.push_back(renderer_->ballVisible(b, scene.robots));
}

// Forth and back over the rendered frames, by the absolute index: cameras sharing an epoch
// show the same frame.
SyntheticSource::ReplayPosition SyntheticSource::replayPosition(std::int64_t index) const {
  const std::int64_t n = static_cast<std::int64_t>(replay_.size()), cycle = 2 * n - 2;
  const std::int64_t m = ((index % cycle) + cycle) % cycle;
  return {replay_[static_cast<std::size_t>(m >= n ? cycle - m : m)], m >= n};
}

bool SyntheticSource::renderReplay(std::string& error) {
  ScenarioConfig scenario;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    scenario = scenario_;
  }
  try {
    GameSimulator sim(scenario, field_, patterns_.maxRobotsPerTeam());  // from the game's start
    std::vector<ReplayFrame> frames(static_cast<std::size_t>(replay_frames_));
    for (std::size_t i = 0; i < frames.size(); ++i) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (interrupted_) return false;
      }
      ReplayFrame& f = frames[i];
      f.scene = sim.state();
      f.scene.time = static_cast<double>(i) * period_;
      f.image.create(format_.height, format_.width, format_.cv_type);
      renderInto(f.scene, static_cast<std::int64_t>(i), f.image, f.encoding, f.robot_visible, f.ball_visible);
      sim.step(period_);
    }
    replay_ = std::move(frames);
    return true;
  } catch (const std::exception& e) {
    error = std::string("rendering the replay failed: ") + e.what();
    return false;
  }
}

}  // namespace soccer_vision
