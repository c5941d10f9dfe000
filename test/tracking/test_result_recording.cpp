#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "soccer_vision/tracking/result_recording.h"

using namespace soccer_vision;

namespace {

TrackerOutput sampleOutput(double stamp) {
  TrackerOutput out;
  out.stamp = stamp;
  TrackedRobot a, b;
  a.team = Team::Yellow;
  a.id = 3;
  a.x = 1.2041;
  a.y = -0.5512;
  a.theta = 1.5708;
  a.confidence = 0.93;
  a.visible = true;
  b.team = Team::Blue;
  b.id = -1;  // team-only
  b.x = -2.0;
  b.visible = false;  // predicted only
  b.confidence = 0.4;
  out.robots = {a, b};
  TrackedBall primary, other;
  primary.primary = true;
  primary.x = 0.12;
  primary.y = 0.003;
  primary.visible = true;
  primary.confidence = 0.8;
  other.x = 3.0;
  other.visible = true;
  out.balls = {primary, other};
  return out;
}

std::string tempPath(const char* name) {
  return (::testing::TempDir().empty() ? std::string("/tmp/") : ::testing::TempDir()) + name;
}

}  // namespace

TEST(ResultRecording, ConvertsTrackerOutputToFrameRecords) {
  const auto all = toFrameRecord(sampleOutput(1700000000.016667));
  EXPECT_DOUBLE_EQ(all.stamp, 1700000000.016667);
  ASSERT_EQ(all.robots.size(), 2u);
  EXPECT_EQ(all.robots[0].team, Team::Yellow);
  EXPECT_EQ(all.robots[0].id, 3);
  EXPECT_DOUBLE_EQ(all.robots[0].theta, 1.5708);
  EXPECT_EQ(*all.robots[0].confidence, 0.93);
  EXPECT_EQ(all.robots[1].id, -1);
  EXPECT_FALSE(*all.robots[1].visible);
  ASSERT_EQ(all.balls.size(), 1u);  // the primary only
  EXPECT_DOUBLE_EQ(all.balls[0].x, 0.12);

  RecordOptions measured_only;
  measured_only.include_unmeasured = false;
  measured_only.all_balls = true;
  const auto some = toFrameRecord(sampleOutput(1.0), measured_only);
  EXPECT_EQ(some.robots.size(), 1u);
  EXPECT_EQ(some.balls.size(), 2u);
}

TEST(ResultRecording, WriterStreamsReadableJsonLines) {
  const std::string path = tempPath("soccer_vision_results_test.jsonl");
  {
    JsonLinesWriter writer(path);
    writer.write(toFrameRecord(sampleOutput(10.0)));
    // Flushed per frame: readable while the writer is still open.
    EXPECT_EQ(readJsonLines(path).size(), 1u);
    writer.write(toFrameRecord(sampleOutput(10.016667)));
    EXPECT_EQ(writer.written(), 2u);
  }
  {
    JsonLinesWriter append(path, true);
    append.write(toFrameRecord(sampleOutput(10.033333)));
  }
  const auto frames = readJsonLines(path);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_DOUBLE_EQ(frames[2].stamp, 10.033333);
  ASSERT_EQ(frames[0].robots.size(), 2u);
  EXPECT_NEAR(frames[0].robots[0].x, 1.2041, 1e-9);
  EXPECT_NEAR(frames[0].robots[0].y, -0.5512, 1e-9);
  EXPECT_EQ(frames[0].robots[1].id, -1);
  EXPECT_NEAR(*frames[0].balls[0].confidence, 0.8, 1e-9);
  { JsonLinesWriter truncate(path); }
  EXPECT_TRUE(readJsonLines(path).empty());
  std::remove(path.c_str());
  EXPECT_THROW(JsonLinesWriter("/nonexistent-dir/results.jsonl"), std::runtime_error);
}
