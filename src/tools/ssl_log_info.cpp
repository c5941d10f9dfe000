// ssl_log_info: what a league log file (docs/ssl.md#log-files) holds: records by type, the
// time span, and its vision packets decoded: detection frames per camera, geometry packets
// (with the field's size), tracked frames. Exit status 0, 2 on bad usage or a file that is not
// a log file or holds a packet that does not decode.
#include <cstdint>
#include <cstdio>
#include <exception>
#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "soccer_vision/ssl/log_file.h"
#include "ssl_vision_wrapper.pb.h"
#include "ssl_vision_wrapper_tracked.pb.h"
#include "tool_command_line.h"

namespace {

namespace ssl = soccer_vision::ssl;

int info(const std::string& path) {
  ssl::LogReader reader(path);
  std::map<std::int32_t, long> by_type;
  std::map<std::uint32_t, long> detections_by_camera;
  long geometry = 0, tracked = 0, records = 0;
  std::int64_t first_ns = 0, last_ns = 0;
  std::string field = "none";
  while (const auto record = reader.next()) {
    if (records++ == 0) first_ns = record->receive_time_ns;
    last_ns = record->receive_time_ns;
    ++by_type[record->type];
    const std::string where = path + ": record " + std::to_string(records);
    if (record->type == static_cast<std::int32_t>(ssl::LogMessageType::Vision2014)) {
      SSL_WrapperPacket packet;
      if (!packet.ParseFromString(record->payload))
        throw std::runtime_error(where + ": not an SSL_WrapperPacket");
      if (packet.has_detection()) ++detections_by_camera[packet.detection().camera_id()];
      if (packet.has_geometry()) {
        ++geometry;
        field = std::to_string(packet.geometry().field().field_length()) + " x " +
                std::to_string(packet.geometry().field().field_width()) + " mm, " +
                std::to_string(packet.geometry().calib_size()) + " camera(s)";
      }
    } else if (record->type == static_cast<std::int32_t>(ssl::LogMessageType::VisionTracker2020)) {
      TrackerWrapperPacket packet;
      if (!packet.ParseFromString(record->payload))
        throw std::runtime_error(where + ": not a TrackerWrapperPacket");
      tracked += packet.has_tracked_frame();
    }
  }
  std::printf("%s: %ld records over %.3f s\n", path.c_str(), records,
              static_cast<double>(last_ns - first_ns) * 1e-9);
  for (const auto& [type, count] : by_type) std::printf("  type %d: %ld records\n", type, count);
  for (const auto& [camera, count] : detections_by_camera) {
    std::printf("  detection frames of camera %u: %ld\n", camera, count);
  }
  std::printf("  geometry packets: %ld (last: %s)\n  tracked frames: %ld\n", geometry, field.c_str(),
              tracked);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  CLI::App app{
      "ssl_log_info: summarises a league log file (SSL_LOG_FILE): records by type, vision packets decoded.",
      "ssl_log_info"};
  app.add_option("log", path, "the log file")->required()->check(CLI::ExistingFile);
  if (const auto status = soccer_vision::parseCommandLine(app, argc, argv)) return *status;
  try {
    return info(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ssl_log_info: %s\n", e.what());
    return 2;
  }
}
