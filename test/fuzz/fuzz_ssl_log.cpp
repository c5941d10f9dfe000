// A league log file (ssl_log_play, ssl_log_info): the bytes as a file, every record read and
// its payload parsed as the packet its type names. A record's size is bounded before it is
// allocated (log_file.cpp), so no input may allocate more than that.
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

#include "fuzz_target.h"
#include "soccer_vision/ssl/log_file.h"
#include "ssl_vision_wrapper.pb.h"
#include "ssl_vision_wrapper_tracked.pb.h"

namespace {

// One scratch file per process (the reader takes a path, as the tools do), removed at exit.
struct ScratchFile {
  const std::string path = "/tmp/soccer_vision_fuzz_ssl_log_" + std::to_string(getpid()) + ".log";
  ~ScratchFile() { std::remove(path.c_str()); }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ScratchFile scratch;
  const std::string& path = scratch.path;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    soccer_vision::ssl::LogReader reader(path);
    while (const auto record = reader.next()) {
      if (record->type == static_cast<std::int32_t>(soccer_vision::ssl::LogMessageType::Vision2014)) {
        SSL_WrapperPacket packet;
        if (packet.ParseFromString(record->payload) && packet.has_geometry()) {
          (void)packet.geometry().field().field_length();
        }
      } else if (record->type ==
                 static_cast<std::int32_t>(soccer_vision::ssl::LogMessageType::VisionTracker2020)) {
        TrackerWrapperPacket packet;
        (void)packet.ParseFromString(record->payload);
      }
    }
  } catch (const std::exception&) {
  }
  return 0;
}
