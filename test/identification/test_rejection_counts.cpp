// Identification never drops a candidate silently: every team-colour region that ends in no
// robot and every orange cluster that ends in no ball is counted under the check it failed.
#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "region_builder.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/identification/frame_identification.h"

using namespace soccer_vision;
using soccer_vision::test::ballRegion;
using soccer_vision::test::markerRegion;

namespace {

const FieldGeometry kField;
const CameraModel kCamera = CameraModel::defaultCamera(kField, 0);

std::vector<Region> robotRegions(const PatternSet& p, Team team, int id, double x, double y, double theta) {
  std::vector<Region> out;
  for (const auto& m : p.markers(team, id)) {
    out.push_back(markerRegion(kCamera, m.shape, m.color, x, y, theta, p.height(team)));
  }
  return out;
}

Region scaledArea(Region r, double factor) {
  r.area = static_cast<std::uint32_t>(std::lround(r.area * factor));
  return r;
}

}  // namespace

TEST(RejectionCounts, CauseNamesAreDistinctAndStable) {
  std::set<std::string> names;
  for (int i = 0; i < kNumRejectionCauses; ++i)
    names.insert(rejectionCauseName(static_cast<RejectionCause>(i)));
  EXPECT_EQ(names.size(), static_cast<std::size_t>(kNumRejectionCauses));
  EXPECT_STREQ(rejectionCauseName(RejectionCause::Area), "area");
  EXPECT_STREQ(rejectionCauseName(RejectionCause::Confidence), "confidence");
  RejectionCounts c;
  EXPECT_EQ(c.summary(), "none");
  c.add(RejectionCause::Gate, 2);
  c.add(RejectionCause::BallArea);
  EXPECT_EQ(c.total(), 3);
  EXPECT_EQ(c.summary(), "gate 2, ball_area 1");
}

// One listing for JSON, diagnostics and the summary: every cause in the enum's order, or
// the counted ones only.
TEST(RejectionCounts, NamedListsEveryCauseOrTheCountedOnes) {
  RejectionCounts counts;
  counts.add(RejectionCause::Confidence, 2);
  counts.add(RejectionCause::Area);
  const auto all = counts.named(false);
  ASSERT_EQ(all.size(), static_cast<std::size_t>(kNumRejectionCauses));
  for (int i = 0; i < kNumRejectionCauses; ++i) {
    const auto cause = static_cast<RejectionCause>(i);
    EXPECT_STREQ(all[i].first, rejectionCauseName(cause));
    EXPECT_EQ(all[i].second, counts[cause]);
  }
  const auto counted = counts.named(true);
  ASSERT_EQ(counted.size(), 2u);
  EXPECT_STREQ(counted[0].first, "area");
  EXPECT_EQ(counted[0].second, 1);
  EXPECT_STREQ(counted[1].first, "confidence");
  EXPECT_EQ(counted[1].second, 2);
  EXPECT_EQ(counts.summary(), "area 1, confidence 2");
  EXPECT_EQ(RejectionCounts().summary(), "none");
}

TEST(RejectionCounts, CompleteRobotsAndABallRejectNothing) {
  const PatternSet p = PatternSet::twoTag();
  std::vector<Region> regions = robotRegions(p, Team::Blue, 1, -2.0, 0.5, 0.3);
  for (const Region& r : robotRegions(p, Team::Yellow, 4, -1.0, -1.0, -2.0)) regions.push_back(r);
  regions.push_back(ballRegion(kCamera, {-1.5, 1.2, 0.0215}));
  const CameraFrameDetections d = FrameIdentifier(kCamera, p, kField).identify(regions);
  EXPECT_EQ(d.robots.size(), 2u);
  EXPECT_EQ(d.balls.size(), 1u);
  EXPECT_EQ(d.rejections.total(), 0) << d.rejections.summary();
}

// The two-tag robot without its role tag has no id: not reported, but counted.
TEST(RejectionCounts, ATeamTagWithoutIdMarkersIsUnpaired) {
  const PatternSet p = PatternSet::twoTag();
  std::vector<Region> regions = robotRegions(p, Team::Blue, 1, -2.0, 0.5, 0.3);
  regions.push_back(robotRegions(p, Team::Yellow, 2, -1.0, 1.0, 1.0).front());  // the team tag alone
  const CameraFrameDetections d = FrameIdentifier(kCamera, p, kField).identify(regions);
  EXPECT_EQ(d.robots.size(), 1u);
  EXPECT_EQ(d.rejections[RejectionCause::Unpaired], 1) << d.rejections.summary();
  EXPECT_EQ(d.rejections.total(), 1) << d.rejections.summary();
}

// The case of the bring-up report: team_only markers smaller than the pattern says are
// dropped for their area or, near the gate, for their confidence: both counted.
TEST(RejectionCounts, TooSmallTeamMarkersCountAsAreaOrConfidence) {
  const PatternSet p = PatternSet::teamOnly();
  const Region marker = robotRegions(p, Team::Blue, -1, -2.0, 0.5, 0).front();
  const FrameIdentifier identify(kCamera, p, kField);
  // ln(0.45) / 0.35 = -2.28: confidence exp(-2.6) = 0.074 >= 0.05, reported.
  EXPECT_EQ(identify.identify({scaledArea(marker, 0.45)}).robots.size(), 1u);
  // ln(0.4) / 0.35 = -2.62: confidence exp(-3.43) = 0.032 < 0.05, inside the area gate (1/3.5).
  const CameraFrameDetections weak = identify.identify({scaledArea(marker, 0.4)});
  EXPECT_TRUE(weak.robots.empty());
  EXPECT_EQ(weak.rejections[RejectionCause::Confidence], 1) << weak.rejections.summary();
  // A fifth: below the gate, above its square, it would be an unsure robot, but ln(0.2) /
  // 0.35 = -4.6 leaves a confidence of 3e-5.
  const CameraFrameDetections small = identify.identify({scaledArea(marker, 0.2)});
  EXPECT_TRUE(small.robots.empty());
  EXPECT_EQ(small.rejections[RejectionCause::Confidence], 1) << small.rejections.summary();
  // A fourteenth is below the gate squared (1/3.5²).
  const CameraFrameDetections tiny = identify.identify({scaledArea(marker, 1.0 / 14)});
  EXPECT_TRUE(tiny.robots.empty());
  EXPECT_EQ(tiny.rejections[RejectionCause::Area], 1) << tiny.rejections.summary();
  EXPECT_EQ(tiny.rejections.total(), 1);
}

// Two robots showing the same (team, id): the better one is reported, the other counted.
TEST(RejectionCounts, ASecondRobotWithATakenIdIsAConflict) {
  const PatternSet p = PatternSet::twoTag();
  std::vector<Region> regions = robotRegions(p, Team::Blue, 3, -2.0, 0.5, 0.3);
  for (const Region& r : robotRegions(p, Team::Blue, 3, -1.0, -1.5, 2.0)) regions.push_back(r);
  const CameraFrameDetections d = FrameIdentifier(kCamera, p, kField).identify(regions);
  EXPECT_EQ(d.robots.size(), 1u);
  EXPECT_EQ(d.rejections[RejectionCause::Conflict], 1) << d.rejections.summary();
  EXPECT_EQ(d.rejections.total(), 1);
}

// A role tag far too large for its place: the pair fails the area check.
TEST(RejectionCounts, AnOversizedIdMarkerCountsAsArea) {
  const PatternSet p = PatternSet::twoTag();
  std::vector<Region> regions = robotRegions(p, Team::Yellow, 2, -2.0, 0.5, 0.3);
  ASSERT_EQ(regions.size(), 2u);  // team tag, role tag
  regions[1] = scaledArea(regions[1], 6.0);
  const CameraFrameDetections d = FrameIdentifier(kCamera, p, kField).identify(regions);
  EXPECT_TRUE(d.robots.empty());
  EXPECT_EQ(d.rejections[RejectionCause::Area], 1) << d.rejections.summary();
}

TEST(RejectionCounts, BallsOffTheCarpetOfTheWrongSizeOrBeyondTheLimitAreCounted) {
  const PatternSet p = PatternSet::twoTag();
  IdentificationParams params;
  params.balls.max_candidates = 2;
  const FrameIdentifier identify(kCamera, p, kField, params);
  std::vector<Region> regions;
  regions.push_back(ballRegion(kCamera, {-1.0, 0.0, 0.0215}));
  regions.push_back(ballRegion(kCamera, {-2.0, 1.0, 0.0215}));
  regions.push_back(ballRegion(kCamera, {-3.0, -1.0, 0.0215}));                   // one more than allowed
  regions.push_back(scaledArea(ballRegion(kCamera, {-1.0, -2.0, 0.0215}), 5.0));  // too large
  const Eigen::Vector3d outside(-4.95, 1.0, 0.0215);                              // beyond carpet + margin
  const auto px = kCamera.project(outside);
  ASSERT_TRUE(px && kCamera.inImage(*px, 6));
  regions.push_back(ballRegion(kCamera, outside));
  const CameraFrameDetections d = identify.identify(regions);
  EXPECT_EQ(d.balls.size(), 2u);
  EXPECT_EQ(d.rejections[RejectionCause::BallSurplus], 1) << d.rejections.summary();
  EXPECT_EQ(d.rejections[RejectionCause::BallArea], 1) << d.rejections.summary();
  EXPECT_EQ(d.rejections[RejectionCause::BallOffField], 1) << d.rejections.summary();
  EXPECT_EQ(d.rejections.total(), 3);
}

// The wall at the carpet's edge keeps a ball's centre 21.5 mm inside it: a ball there is
// one, an orange shoe 5 cm beyond the carpet is not (BallDetectionParams::field_margin).
TEST(RejectionCounts, ABallAtTheWallIsKeptAnOrangeThingJustBeyondTheCarpetIsNot) {
  const PatternSet p = PatternSet::twoTag();
  const FrameIdentifier identify(kCamera, p, kField);
  const double edge = kField.halfLength() + kField.boundary;  // the carpet's end
  const Eigen::Vector3d at_wall(-(edge - 0.0215), 1.0, 0.0215), beyond(-(edge + 0.05), -1.0, 0.0215);
  for (const auto& where : {at_wall, beyond}) {
    const auto px = kCamera.project(where);
    ASSERT_TRUE(px && kCamera.inImage(*px, 6));
  }
  const CameraFrameDetections d =
      identify.identify({ballRegion(kCamera, at_wall), ballRegion(kCamera, beyond)});
  ASSERT_EQ(d.balls.size(), 1u);
  EXPECT_NEAR(d.balls[0].x, at_wall.x(), 0.005);
  EXPECT_EQ(d.rejections[RejectionCause::BallOffField], 1) << d.rejections.summary();
}
