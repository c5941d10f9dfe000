// ssl_log_play: plays a league log file (docs/ssl.md#log-files) back onto the SSL UDP ports:
// VISION_2014 records to the detection port, VISION_TRACKER_2020 records to the tracked port,
// at their recorded pace (or faster). The address defaults to 127.0.0.1: sending to the
// league's multicast group has to be asked for. Exit status: 0 all sent, 1 send errors, 2 bad
// usage or input (not a log file, a cut record, an invalid address).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "soccer_vision/ssl/log_file.h"
#include "soccer_vision/ssl/udp_sender.h"
#include "tool_command_line.h"

namespace {

namespace ssl = soccer_vision::ssl;

struct Options {
  std::string log;
  std::string address = "127.0.0.1";
  int detection_port = 10006;
  int tracked_port = 10010;
  std::string interface;
  double speed = 1.0;
  bool fast = false;
};

int play(const Options& o) {
  ssl::LogReader reader(o.log);
  ssl::UdpSender detection(o.address, o.detection_port, o.interface);
  ssl::UdpSender tracked(o.address, o.tracked_port, o.interface);
  long sent_detection = 0, sent_tracked = 0, skipped = 0, errors = 0;
  std::int64_t first_ns = 0;
  bool started = false;
  const auto wall_start = std::chrono::steady_clock::now();
  while (const auto record = reader.next()) {
    ssl::UdpSender* sender = nullptr;
    if (record->type == static_cast<std::int32_t>(ssl::LogMessageType::Vision2014)) sender = &detection;
    if (record->type == static_cast<std::int32_t>(ssl::LogMessageType::VisionTracker2020)) sender = &tracked;
    if (!sender) {
      ++skipped;  // referee and other messages: not ours to replay
      continue;
    }
    if (!started) {
      first_ns = record->receive_time_ns;
      started = true;
    }
    if (!o.fast) {
      // The record's offset from the first one, scaled by the speed; a clock jump backwards
      // in the file sends at once.
      const double offset_s = static_cast<double>(record->receive_time_ns - first_ns) * 1e-9 / o.speed;
      if (offset_s > 0) std::this_thread::sleep_until(wall_start + std::chrono::duration<double>(offset_s));
    }
    if (!sender->send(record->payload)) {
      ++errors;
      std::fprintf(stderr, "send failed: %s\n", sender->lastError().c_str());
      continue;
    }
    (sender == &detection ? sent_detection : sent_tracked)++;
  }
  std::printf(
      "%s: sent %ld detection/geometry and %ld tracked packets to %s (ports %d, %d); %ld other records "
      "skipped, %ld send errors\n",
      o.log.c_str(), sent_detection, sent_tracked, o.address.c_str(), o.detection_port, o.tracked_port,
      skipped, errors);
  return errors == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"ssl_log_play: plays a league log file (SSL_LOG_FILE) back onto the SSL-Vision UDP ports.",
               "ssl_log_play"};
  app.add_option("log", o.log, "the log file")->required()->check(CLI::ExistingFile);
  app.add_option("--address", o.address, "IPv4 destination (224.5.23.2 is the league's multicast group)")
      ->capture_default_str();
  app.add_option("--detection-port", o.detection_port, "port of VISION_2014 records")
      ->check(CLI::Range(1, 65535))
      ->capture_default_str();
  app.add_option("--tracked-port", o.tracked_port, "port of VISION_TRACKER_2020 records")
      ->check(CLI::Range(1, 65535))
      ->capture_default_str();
  app.add_option("--interface", o.interface, "network interface for multicast");
  app.add_option("--speed", o.speed, "playback speed (2: twice as fast)")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  app.add_flag("--fast", o.fast, "send without waiting between records");
  if (const auto status = soccer_vision::parseCommandLine(app, argc, argv)) return *status;
  try {
    return play(o);
  } catch (const std::exception& e) {  // not a log file, a cut record, an invalid address
    std::fprintf(stderr, "ssl_log_play: %s\n", e.what());
    return 2;
  }
}
