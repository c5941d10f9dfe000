// rostest (identification_recall.test): the Identification nodelet in a manager, fed blobs
// a perfect segmentation of an SSL robot would give. In one frame a dot is missing and the
// three left fit two ids: the nodelet gives the robot the id it identified there a frame
// before (unsure), counts it in /diagnostics, and gives none to a robot seen nowhere near.
#include <cmath>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include <boost/make_shared.hpp>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "identification/region_builder.h"
#include "soccer_vision/BlobArray.h"
#include "soccer_vision/CameraDetections.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/ros/blob_conversions.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/transforms.h"

using namespace soccer_vision;

namespace {

const FieldGeometry kField;
const CameraModel kCamera = CameraModel::defaultCamera(kField, 0);
const PatternSet kSsl = PatternSet::ssl();
constexpr double kT0 = 1700000000.0;
constexpr double kFrame = 1.0 / 60;
constexpr char kOptical[] = "camera_0_optical";

struct Received {
  std::mutex mutex;
  std::map<double, CameraDetectionsConstPtr> detections;  // by stamp
  std::map<std::string, std::string> diagnostics;         // "<status name>/<key>" -> value
};

// Blobs of a yellow robot at (x, y, theta) with all its markers, or without its marker `skip`.
BlobArrayPtr blobs(double stamp, int id, double x, double y, double theta, int skip = -1) {
  auto m = boost::make_shared<BlobArray>();
  m->header.stamp = ros::Time(stamp);
  m->header.frame_id = kOptical;
  m->camera_id = 0;
  m->image_width = static_cast<std::uint32_t>(kCamera.width());
  m->image_height = static_cast<std::uint32_t>(kCamera.height());
  m->global_search = true;
  const auto markers = kSsl.markers(Team::Yellow, id);
  for (std::size_t k = 0; k < markers.size(); ++k) {
    if (static_cast<int>(k) == skip) continue;
    m->blobs.push_back(toBlob(test::markerRegion(kCamera, markers[k].shape, markers[k].color, x, y, theta,
                                                 kSsl.height(Team::Yellow))));
  }
  return m;
}

class IdentificationRecall : public ::testing::Test {
 protected:
  void SetUp() override {
    blobs_pub_ = nh_.advertise<BlobArray>("/camera_0/blobs", 10);
    info_pub_ = nh_.advertise<sensor_msgs::CameraInfo>("/camera_0/camera_info", 1, true);
    detections_sub_ = nh_.subscribe<CameraDetections>("/camera_0/detections", 20,
                                                      [this](const CameraDetectionsConstPtr& d) {
                                                        std::lock_guard<std::mutex> l(received_.mutex);
                                                        received_.detections[d->header.stamp.toSec()] = d;
                                                      });
    diagnostics_sub_ = nh_.subscribe<diagnostic_msgs::DiagnosticArray>(
        "/diagnostics", 20, [this](const diagnostic_msgs::DiagnosticArrayConstPtr& a) {
          std::lock_guard<std::mutex> l(received_.mutex);
          for (const auto& s : a->status)
            for (const auto& kv : s.values) received_.diagnostics[s.name + "/" + kv.key] = kv.value;
        });
    tf_.sendTransform(toTransformStamped(kCamera.fieldTCamera(), "field", kOptical, ros::Time::now()));
    info_pub_.publish(toCameraInfo(kCamera, kOptical));
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
    while (ros::WallTime::now() < deadline && blobs_pub_.getNumSubscribers() == 0)
      ros::WallDuration(0.05).sleep();
  }

  // The detections of the frame at `stamp`, waited for.
  CameraDetectionsConstPtr detectionsAt(double stamp, double timeout = 5.0) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> l(received_.mutex);
        const auto it = received_.detections.find(ros::Time(stamp).toSec());
        if (it != received_.detections.end()) return it->second;
      }
      ros::WallDuration(0.01).sleep();
    }
    return nullptr;
  }

  static std::optional<RobotPose> yellow(const CameraDetections& d, int id) {
    for (const auto& r : d.robots)
      if (r.team == RobotPose::TEAM_YELLOW && r.id == id) return r;
    return std::nullopt;
  }

  ros::NodeHandle nh_;
  ros::Publisher blobs_pub_, info_pub_;
  ros::Subscriber detections_sub_, diagnostics_sub_;
  tf2_ros::StaticTransformBroadcaster tf_;
  Received received_;
};

TEST_F(IdentificationRecall, AnAmbiguousRobotTakesTheIdItHadThereAFrameBefore) {
  ASSERT_GT(blobs_pub_.getNumSubscribers(), 0u) << "the Identification nodelet did not subscribe";
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const int id = 5;
  double x = -1.5, y = -1.5, theta = 30 * M_PI / 180;
  // Complete robots until the nodelet has its camera model (tf and camera_info arrive first).
  double stamp = kT0;
  CameraDetectionsConstPtr first;
  for (int k = 0; k < 100 && !(first && yellow(*first, id)); ++k) {
    stamp = kT0 + k * kFrame;
    blobs_pub_.publish(blobs(stamp, id, x, y, theta));
    first = detectionsAt(stamp, 0.2);
  }
  ASSERT_TRUE(first && yellow(*first, id)) << "no complete robot identified";
  EXPECT_GT(yellow(*first, id)->confidence, 0.5);

  // A frame later, 2 m/s on: the front-right dot (marker 1) is missing; the three left fit
  // ids 5 and 13.
  x += 2.0 * kFrame;
  stamp += kFrame;
  blobs_pub_.publish(blobs(stamp, id, x, y, theta, 1));
  const CameraDetectionsConstPtr recalled = detectionsAt(stamp);
  ASSERT_TRUE(recalled);
  const auto five = yellow(*recalled, id);
  ASSERT_TRUE(five) << "the ambiguous robot got no id";
  EXPECT_LE(five->confidence, 0.15 + 1e-6);
  EXPECT_LT(std::hypot(five->x - x, five->y - y), 0.001);

  // A second later, elsewhere: nothing to recall, no id (never a guessed one).
  stamp += 1.0;
  blobs_pub_.publish(blobs(stamp, id, 1.0, -1.0, theta, 1));
  const CameraDetectionsConstPtr alone = detectionsAt(stamp);
  ASSERT_TRUE(alone);
  EXPECT_TRUE(alone->robots.empty());

  // Counted in the diagnostics (reported every second).
  const std::string key =
      "camera_0/identification: identification/reported unsure: id recalled from the last frames";
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(5.0);
  std::string value;
  while (ros::WallTime::now() < deadline && value != "1") {
    ros::WallDuration(0.1).sleep();
    std::lock_guard<std::mutex> l(received_.mutex);
    const auto it = received_.diagnostics.find(key);
    if (it != received_.diagnostics.end()) value = it->second;
  }
  EXPECT_EQ(value, "1");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_identification_recall");
  return RUN_ALL_TESTS();
}
