#include "soccer_vision/ssl/log_file.h"

#include <cstring>
#include <stdexcept>

namespace soccer_vision::ssl {

namespace {

// Records larger than this are taken for a corrupt file rather than read into memory.
constexpr std::int32_t kMaxPayload = 64 * 1024 * 1024;

template <typename T>
void putBigEndian(std::string& out, T value) {
  const auto u = static_cast<std::uint64_t>(value);
  for (int shift = 8 * (static_cast<int>(sizeof(T)) - 1); shift >= 0; shift -= 8) {
    out.push_back(static_cast<char>((u >> shift) & 0xFF));
  }
}

template <typename T>
T getBigEndian(const unsigned char* in) {
  std::uint64_t u = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) u = (u << 8) | in[i];
  return static_cast<T>(u);
}

}  // namespace

LogWriter::LogWriter(const std::string& path) : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw std::runtime_error("SSL log " + path + ": cannot create the file");
  std::string header(kLogHeader);
  putBigEndian<std::int32_t>(header, kLogVersion);
  out_.write(header.data(), static_cast<std::streamsize>(header.size()));
  if (!out_) throw std::runtime_error("SSL log " + path + ": cannot write the header");
}

void LogWriter::write(const LogRecord& record) {
  std::string framing;
  putBigEndian<std::int64_t>(framing, record.receive_time_ns);
  putBigEndian<std::int32_t>(framing, record.type);
  putBigEndian<std::int32_t>(framing, static_cast<std::int32_t>(record.payload.size()));
  out_.write(framing.data(), static_cast<std::streamsize>(framing.size()));
  out_.write(record.payload.data(), static_cast<std::streamsize>(record.payload.size()));
  if (!out_) throw std::runtime_error("SSL log " + path_ + ": write failed");
}

void LogWriter::flush() {
  out_.flush();
  if (!out_) throw std::runtime_error("SSL log " + path_ + ": write failed");
}

LogReader::LogReader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
  if (!in_) throw std::runtime_error("SSL log " + path + ": cannot open the file");
  constexpr std::size_t header_size = sizeof(kLogHeader) - 1;
  unsigned char header[header_size + 4];
  in_.read(reinterpret_cast<char*>(header), sizeof header);
  if (in_.gcount() != static_cast<std::streamsize>(sizeof header) ||
      std::memcmp(header, kLogHeader, header_size) != 0) {
    throw std::runtime_error("SSL log " + path + ": no SSL_LOG_FILE header");
  }
  const auto version = getBigEndian<std::int32_t>(header + header_size);
  if (version != kLogVersion) {
    throw std::runtime_error("SSL log " + path + ": version " + std::to_string(version) + ", expected " +
                             std::to_string(kLogVersion));
  }
}

std::optional<LogRecord> LogReader::next() {
  const std::streamoff offset = in_.tellg();
  unsigned char framing[16];
  in_.read(reinterpret_cast<char*>(framing), sizeof framing);
  if (in_.gcount() == 0 && in_.eof()) return std::nullopt;
  const std::string where = "SSL log " + path_ + ": record at byte " + std::to_string(offset);
  if (in_.gcount() != static_cast<std::streamsize>(sizeof framing))
    throw std::runtime_error(where + " truncated");
  LogRecord record;
  record.receive_time_ns = getBigEndian<std::int64_t>(framing);
  record.type = getBigEndian<std::int32_t>(framing + 8);
  const auto size = getBigEndian<std::int32_t>(framing + 12);
  if (size < 0 || size > kMaxPayload) {
    throw std::runtime_error(where + ": size " + std::to_string(size) + " outside 0.." +
                             std::to_string(kMaxPayload));
  }
  record.payload.resize(static_cast<std::size_t>(size));
  in_.read(record.payload.data(), size);
  if (in_.gcount() != size) throw std::runtime_error(where + ": payload truncated");
  return record;
}

}  // namespace soccer_vision::ssl
