// The league's log files (docs/ssl.md): the header "SSL_LOG_FILE" and an int32 version 1, then
// records of int64 receive time [ns], int32 message type, int32 payload size and the payload
// (a serialised packet); every integer big-endian.
#pragma once

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>

namespace soccer_vision::ssl {

// The league's message types; soccer_vision writes the two vision ones.
enum class LogMessageType : std::int32_t {
  Blank = 0,
  Unknown = 1,
  SslVision2010 = 2,
  SslRefbox2013 = 3,
  Vision2014 = 4,         // SSL_WrapperPacket (detection port)
  VisionTracker2020 = 5,  // TrackerWrapperPacket (tracked port)
};

inline constexpr char kLogHeader[] = "SSL_LOG_FILE";
inline constexpr std::int32_t kLogVersion = 1;

struct LogRecord {
  std::int64_t receive_time_ns = 0;  // Unix time
  std::int32_t type = 0;             // a LogMessageType; other values are kept as they are
  std::string payload;
};

class LogWriter {
 public:
  // Creates (truncates) the file and writes the header; throws std::runtime_error naming the file.
  explicit LogWriter(const std::string& path);
  // Throws std::runtime_error naming the file when the write fails (disk full, ...).
  void write(const LogRecord& record);
  void flush();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ofstream out_;
};

class LogReader {
 public:
  // Opens the file and checks the header and the version; throws std::runtime_error naming the
  // file and what is wrong.
  explicit LogReader(const std::string& path);
  // The next record; nullopt at the end of the file. A truncated record or a negative size
  // throws std::runtime_error naming the file and the record's byte offset.
  std::optional<LogRecord> next();

 private:
  std::string path_;
  std::ifstream in_;
};

}  // namespace soccer_vision::ssl
