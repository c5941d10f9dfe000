#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "soccer_vision/ssl/detection_packet.h"
#include "soccer_vision/ssl/log_file.h"

using namespace soccer_vision;

namespace {

std::string tempPath(const std::string& name) {
  return testing::TempDir() + "/" + name + "_" + std::to_string(getpid()) + ".log";
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace

TEST(SslLogFile, HeaderAndRecordFramingByteForByte) {
  const std::string path = tempPath("framing");
  {
    ssl::LogWriter writer(path);
    writer.write({0x0102030405060708LL, static_cast<int>(ssl::LogMessageType::Vision2014), "abc"});
    writer.write({-2, static_cast<int>(ssl::LogMessageType::VisionTracker2020), ""});
  }
  const std::string expected = std::string("SSL_LOG_FILE") + std::string("\x00\x00\x00\x01", 4) +
                               std::string("\x01\x02\x03\x04\x05\x06\x07\x08", 8) +  // time, big-endian
                               std::string("\x00\x00\x00\x04", 4) +                  // VISION_2014
                               std::string("\x00\x00\x00\x03", 4) + "abc" +          // size, payload
                               std::string("\xff\xff\xff\xff\xff\xff\xff\xfe", 8) +  // -2 ns
                               std::string("\x00\x00\x00\x05", 4) +                  // VISION_TRACKER_2020
                               std::string("\x00\x00\x00\x00", 4);
  EXPECT_EQ(readAll(path), expected);
  std::remove(path.c_str());
}

TEST(SslLogFile, WrittenPacketsReadBackTheSame) {
  const std::string path = tempPath("roundtrip");
  CameraFrameDetections frame;
  frame.stamp = 1764700000.25;
  frame.camera_id = 1;
  frame.balls.resize(1);
  frame.balls[0].x = 1.0;
  const std::string packet = ssl::detectionPacket(frame, 5, 1764700000.26).SerializeAsString();
  {
    ssl::LogWriter writer(path);
    for (int i = 0; i < 3; ++i) {
      writer.write({1764700000250000000LL + i, static_cast<int>(ssl::LogMessageType::Vision2014), packet});
    }
  }
  ssl::LogReader reader(path);
  for (int i = 0; i < 3; ++i) {
    const auto record = reader.next();
    ASSERT_TRUE(record.has_value());
    EXPECT_EQ(record->receive_time_ns, 1764700000250000000LL + i);
    EXPECT_EQ(record->type, 4);
    ASSERT_EQ(record->payload, packet);
    SSL_WrapperPacket decoded;
    ASSERT_TRUE(decoded.ParseFromString(record->payload));
    EXPECT_DOUBLE_EQ(decoded.detection().t_capture(), 1764700000.25);
    EXPECT_FLOAT_EQ(decoded.detection().balls(0).x(), 1000.0f);
  }
  EXPECT_FALSE(reader.next().has_value());
  std::remove(path.c_str());
}

TEST(SslLogFile, BadHeaderVersionOrTruncationNamesTheFile) {
  const std::string path = tempPath("bad");
  writeBytes(path, "NOT_A_LOG_FILE__");
  try {
    ssl::LogReader reader(path);
    FAIL() << "accepted a file without the header";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  writeBytes(path, std::string("SSL_LOG_FILE\x00\x00\x00\x02", 16));
  EXPECT_THROW(ssl::LogReader{path}, std::runtime_error);
  // A record cut in its payload: header (16 bytes), framing (16), 2 of 10 payload bytes.
  writeBytes(path, std::string("SSL_LOG_FILE\x00\x00\x00\x01", 16) + std::string(8, '\0') +
                       std::string("\x00\x00\x00\x04\x00\x00\x00\x0a", 8) + "ab");
  ssl::LogReader reader(path);
  try {
    reader.next();
    FAIL() << "read a truncated record";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("byte 16"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}
