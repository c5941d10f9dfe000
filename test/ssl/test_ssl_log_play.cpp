// ssl_log_play and ssl_log_info as a user runs them: a log file written with LogWriter comes back as the same
// datagrams on the two ports of 127.0.0.1; bad usage and bad input exit with 2.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "soccer_vision/ssl/log_file.h"
#include "ssl_vision_wrapper.pb.h"
#include "support/loopback_receiver.h"

namespace {

using soccer_vision::test::LoopbackReceiver;

int run(const std::string& arguments) {
  const int status =
      std::system((std::string(SSL_LOG_PLAY_BIN) + " " + arguments + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(SslLogPlay, SendsEveryVisionRecordToItsPortInOrder) {
  const std::string path = testing::TempDir() + "/ssl_log_play_" + std::to_string(getpid()) + ".log";
  {
    soccer_vision::ssl::LogWriter writer(path);
    writer.write({1000000000, 4, "detection 1"});
    writer.write({1010000000, 5, "tracked 1"});
    writer.write({1020000000, 3, "referee: not replayed"});
    writer.write({1030000000, 4, "detection 2"});
  }
  LoopbackReceiver detection, tracked;
  ASSERT_EQ(run(path + " --address 127.0.0.1 --detection-port " + std::to_string(detection.port) +
                " --tracked-port " + std::to_string(tracked.port)),
            0);
  EXPECT_EQ(detection.receive(), "detection 1");
  EXPECT_EQ(detection.receive(), "detection 2");
  EXPECT_EQ(tracked.receive(), "tracked 1");
  std::remove(path.c_str());
}

TEST(SslLogPlay, BadUsageAndBadInputExitWithTwo) {
  EXPECT_EQ(run("--help"), 0);
  EXPECT_EQ(run(""), 2);
  EXPECT_EQ(run("/no/such/file.log"), 2);
  EXPECT_EQ(run(std::string(SOCCER_VISION_SOURCE_DIR) + "/README.md --detection-port 0"), 2);
  EXPECT_EQ(run(std::string(SOCCER_VISION_SOURCE_DIR) + "/README.md --speed 0"), 2);
  EXPECT_EQ(run(std::string(SOCCER_VISION_SOURCE_DIR) + "/README.md --fast"), 2);  // not a log file
}

TEST(SslLogInfo, CountsRecordsAndDecodesTheVisionPackets) {
  const std::string path = testing::TempDir() + "/ssl_log_info_" + std::to_string(getpid()) + ".log";
  {
    soccer_vision::ssl::LogWriter writer(path);
    SSL_WrapperPacket detection;
    detection.mutable_detection()->set_frame_number(1);
    detection.mutable_detection()->set_t_capture(1);
    detection.mutable_detection()->set_t_sent(1);
    detection.mutable_detection()->set_camera_id(3);
    writer.write({1000000000, 4, detection.SerializeAsString()});
    writer.write({1500000000, 4, detection.SerializeAsString()});
    writer.write({2000000000, 3, "referee"});
  }
  const std::string out = path + ".txt";
  const int status =
      std::system((std::string(SSL_LOG_INFO_BIN) + " " + path + " > " + out + " 2>&1").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("3 records over 1.000 s"), std::string::npos) << text;
  EXPECT_NE(text.find("detection frames of camera 3: 2"), std::string::npos) << text;
  {
    soccer_vision::ssl::LogWriter writer(path);
    writer.write({0, 4, std::string("\xff\xff\xff", 3)});  // not a packet
  }
  EXPECT_EQ(
      WEXITSTATUS(std::system((std::string(SSL_LOG_INFO_BIN) + " " + path + " > /dev/null 2>&1").c_str())),
      2);
  std::remove(path.c_str());
  std::remove(out.c_str());
}
