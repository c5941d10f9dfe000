// The calibration UI's HTTP server (cpp-httplib): the static page from a folder and a small
// JSON API over a backend that knows the running system (the CalibrationUi nodelet). It
// validates every request (size, JSON, limits, token) before the backend sees it, runs on its
// own threads, and answers errors as JSON {"error": "..."} with a fitting HTTP status.
//
//   GET  /api/info                            cameras, whether changes need a token / are refused
//   GET  /api/status                          the system's diagnostics, the server's counters
//   GET  /api/cameras/<n>/live.jpg            the latest frame (JPEG, throttled)
//   GET  /api/cameras/<n>/frozen.jpg          the frozen frame
//   GET  /api/cameras/<n>/classification.jpg  the segmentation's live classification
//   GET  /api/cameras/<n>/overlay[?frozen=1]  regions, robots, ball, field lines in pixels
//   POST /api/cameras/<n>/freeze              keep the latest frame for painting samples
//   POST /api/cameras/<n>/calibrate           {"samples": {...}, "save": bool} -> ~calibrate
//   POST /api/cameras/<n>/pose/solve          {"points": [...]} -> pose, RMS, field lines
//   POST /api/cameras/<n>/pose/save           write the solved pose (camera_pose.yaml)
// POSTs need the header `X-Token: <ui_token>` when a token is set (UiAccess).
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "soccer_vision/ui/ui_access.h"
#include "soccer_vision/ui/ui_requests.h"

namespace httplib {
class Server;
}

namespace soccer_vision {

// What the server asks of the running system. Methods are called from the server's threads
// (concurrently); they throw UiRequestError for answers other than 200.
class CalibrationUiBackend {
 public:
  virtual ~CalibrationUiBackend() = default;
  virtual nlohmann::json info() = 0;
  virtual nlohmann::json status() = 0;
  virtual std::string liveJpeg(int camera) = 0;
  virtual std::string frozenJpeg(int camera) = 0;
  virtual std::string classificationJpeg(int camera) = 0;
  virtual nlohmann::json overlay(int camera, bool frozen) = 0;
  virtual nlohmann::json freeze(int camera) = 0;
  virtual nlohmann::json calibrateColors(int camera, const nlohmann::json& body) = 0;
  virtual nlohmann::json solvePose(int camera, const nlohmann::json& body) = 0;
  virtual nlohmann::json savePose(int camera) = 0;
};

struct CalibrationUiSettings {
  std::string address = "127.0.0.1";
  int port = 8085;
  std::string token;    // "" = none
  std::string www_dir;  // the static page
  int threads = 3;      // request threads (a calibration may take one for a second)
  UiRequestLimits limits;
};

class CalibrationUiServer {
 public:
  CalibrationUiServer(CalibrationUiSettings settings, CalibrationUiBackend& backend);
  ~CalibrationUiServer();
  CalibrationUiServer(const CalibrationUiServer&) = delete;
  CalibrationUiServer& operator=(const CalibrationUiServer&) = delete;

  // Binds the port (throws std::runtime_error naming address and port when it cannot) and
  // serves on a thread of its own until stop() or destruction.
  void start();
  void stop();
  int port() const { return bound_port_; }
  const UiAccess& access() const { return access_; }
  // Counters for the status page and diagnostics.
  std::uint64_t requests() const { return requests_; }
  std::uint64_t refused() const { return refused_; }
  std::uint64_t failed() const { return failed_; }

 private:
  void routes();

  CalibrationUiSettings settings_;
  CalibrationUiBackend& backend_;
  UiAccess access_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  int bound_port_ = 0;
  std::atomic<std::uint64_t> requests_{0}, refused_{0}, failed_{0};
};

}  // namespace soccer_vision
