// rostest for bad live input (test/nodelets/bad_input.test): Segmentation, Identification and
// Tracking in one manager, fed by this test. Every case must leave the manager running and
// show up, by cause, in the nodelets' /diagnostics:
//  1. images with a wrong encoding, zero size, a step or data-length mismatch, an absurd
//     size (refused up front) and 10 000 x 10 000 px;
//  2. pure noise at 60 Hz, segmented with a table ~calibrate made on the noise: the frame
//     cost is reported and the frames keep coming;
//  3. camera_info with NaN and with a zero focal length: refused, counted;
//  4. detections whose stamps go backwards and jump (one frame in 2038): tracker resets are
//     counted, tf is held back for the isolated jump.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <random>
#include <string>

#include <boost/make_shared.hpp>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include "soccer_vision/BlobArray.h"
#include "soccer_vision/Calibrate.h"
#include "soccer_vision/CameraDetections.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/ros/conversions.h"

namespace {

class BadInputTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ros::NodeHandle nh, pnh("~");
    pnh.param<std::string>("dir", dir_, "/tmp/soccer_vision_test_bad_input");
    ASSERT_EQ(std::system(("rm -rf '" + dir_ + "' && mkdir -p '" + dir_ + "'").c_str()), 0);
    state_ = new State;
    image_pub_ = new ros::Publisher(nh.advertise<sensor_msgs::Image>("/camera_0/image_raw", 5));
    info_pub_ = new ros::Publisher(nh.advertise<sensor_msgs::CameraInfo>("/camera_0/camera_info", 5));
    detections_pub_ =
        new ros::Publisher(nh.advertise<soccer_vision::CameraDetections>("/camera_0/detections", 5));
    subs_ = new std::vector<ros::Subscriber>;
    subs_->push_back(nh.subscribe<diagnostic_msgs::DiagnosticArray>(
        "/diagnostics", 50, +[](const diagnostic_msgs::DiagnosticArrayConstPtr& a) {
          std::lock_guard<std::mutex> l(state_->mutex);
          for (const auto& st : a->status) {
            for (const auto& kv : st.values) state_->values[st.name + "/" + kv.key] = kv.value;
            ++state_->reports;
          }
        }));
    subs_->push_back(nh.subscribe<soccer_vision::BlobArray>(
        "/camera_0/blobs", 50, +[](const soccer_vision::BlobArrayConstPtr& m) {
          std::lock_guard<std::mutex> l(state_->mutex);
          ++state_->blobs;
          state_->blob_seconds += m->processing_time;
          state_->blob_seconds_max =
              std::max(state_->blob_seconds_max, static_cast<double>(m->processing_time));
        }));
    subs_->push_back(nh.subscribe<tf2_msgs::TFMessage>(
        "/tf", 200, +[](const tf2_msgs::TFMessageConstPtr& m) {
          std::lock_guard<std::mutex> l(state_->mutex);
          for (const auto& t : m->transforms) {
            if (t.header.stamp.sec > 2000000000) ++state_->far_future_tf;
            ++state_->tf;
          }
        }));
    // Publishers connect before anything is sent.
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
    while (ros::WallTime::now() < deadline &&
           (image_pub_->getNumSubscribers() == 0 || info_pub_->getNumSubscribers() < 2 ||
            detections_pub_->getNumSubscribers() == 0))
      ros::WallDuration(0.05).sleep();
  }
  static void TearDownTestSuite() {
    delete subs_;
    delete image_pub_;
    delete info_pub_;
    delete detections_pub_;
    delete state_;
  }

  // A diagnostics value of a nodelet ("<node>: <task>/<key>"), after a fresh report.
  static double value(const std::string& node_task, const std::string& key, double timeout = 10.0) {
    const std::string name = node_task + "/" + key;
    std::uint64_t reports = 0;
    {
      std::lock_guard<std::mutex> l(state_->mutex);
      reports = state_->reports;
    }
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> l(state_->mutex);
        // Wait for reports sent after the call (every nodelet reports at least every second).
        if (state_->reports > reports + 6) {
          const auto it = state_->values.find(name);
          if (it != state_->values.end()) return std::stod(it->second);
        }
      }
      ros::WallDuration(0.05).sleep();
    }
    ADD_FAILURE() << "no diagnostics value " << name;
    return -1;
  }

  static sensor_msgs::ImagePtr image(std::uint32_t width, std::uint32_t height, const std::string& encoding,
                                     std::uint32_t step, std::size_t bytes) {
    auto m = boost::make_shared<sensor_msgs::Image>();
    m->header.stamp = ros::Time::now();
    m->header.frame_id = "camera_0_optical";
    m->width = width;
    m->height = height;
    m->encoding = encoding;
    m->step = step;
    m->data.assign(bytes, 128);
    return m;
  }

  struct State {
    std::mutex mutex;
    std::map<std::string, std::string> values;
    std::uint64_t reports = 0, blobs = 0, tf = 0, far_future_tf = 0;
    double blob_seconds = 0, blob_seconds_max = 0;  // BlobArray.processing_time
  };
  static std::string dir_;
  static State* state_;
  static ros::Publisher *image_pub_, *info_pub_, *detections_pub_;
  static std::vector<ros::Subscriber>* subs_;
  const std::string segmentation_ = "camera_0/segmentation: segmentation";
};

std::string BadInputTest::dir_;
BadInputTest::State* BadInputTest::state_ = nullptr;
ros::Publisher *BadInputTest::image_pub_ = nullptr, *BadInputTest::info_pub_ = nullptr,
               *BadInputTest::detections_pub_ = nullptr;
std::vector<ros::Subscriber>* BadInputTest::subs_ = nullptr;

TEST_F(BadInputTest, BadImagesAreDroppedAndCountedByCause) {
  for (int i = 0; i < 5; ++i) {
    image_pub_->publish(image(64, 48, "mono16", 128, 128 * 48));  // wrong encoding
    ros::WallDuration(0.05).sleep();
    image_pub_->publish(image(0, 0, "bgr8", 0, 0));  // zero size
    ros::WallDuration(0.05).sleep();
    image_pub_->publish(image(64, 48, "bgr8", 100, 100 * 48));  // step < width * 3
    ros::WallDuration(0.05).sleep();
    image_pub_->publish(image(64, 48, "bgr8", 192, 192 * 10));  // data shorter than step * height
    ros::WallDuration(0.05).sleep();
    image_pub_->publish(image(40000, 2, "bgr8", 120000, 240000));  // beyond 16384 px a side
    ros::WallDuration(0.05).sleep();
  }
  image_pub_->publish(image(10000, 10000, "bayer_rggb8", 10000, 100000000));  // 100 MB, no table yet
  EXPECT_GE(value(segmentation_, "dropped: unsupported encoding"), 5);
  EXPECT_GE(value(segmentation_, "dropped: empty/truncated image"), 20);
  EXPECT_GE(value(segmentation_, "dropped: no colour table"), 1)
      << "the 10000 x 10000 frame reaches the table";
}

TEST_F(BadInputTest, NoiseAt60HzIsSegmentedAtABoundedCost) {
  std::mt19937 rng(7);
  auto noise = [&] {
    auto m = image(1280, 1024, "bgr8", 1280 * 3, 1280 * 1024 * 3);
    for (auto& b : m->data) b = static_cast<std::uint8_t>(rng());
    return m;
  };
  // The calibration frame: noise with a carpet-green and a pink patch (slightly noisy), so
  // the two sampled classes are distinct and both keep cells.
  auto frame = noise();
  auto patch = [&](int u0, int v0, int side, std::uint8_t b, std::uint8_t g, std::uint8_t r) {
    for (int v = v0; v < v0 + side; ++v) {
      for (int u = u0; u < u0 + side; ++u) {
        std::uint8_t* p = &frame->data[static_cast<std::size_t>(v) * frame->step + 3 * u];
        const int d = static_cast<int>(rng() % 5) - 2;
        p[0] = static_cast<std::uint8_t>(b + d), p[1] = static_cast<std::uint8_t>(g + d),
        p[2] = static_cast<std::uint8_t>(r + d);
      }
    }
  };
  patch(0, 0, 300, 40, 110, 45);
  patch(500, 500, 200, 170, 70, 240);
  image_pub_->publish(frame);
  ros::WallDuration(0.5).sleep();
  soccer_vision::Calibrate srv;
  srv.request.samples_yaml =
      "carpet:\n  - [[10, 10], [290, 10], [290, 290], [10, 290]]\n"
      "pink:\n  - [[510, 510], [690, 510], [690, 690], [510, 690]]\n";
  srv.request.save = true;
  srv.request.path = "made_by_calibrate.svct";
  ASSERT_TRUE(ros::service::waitForService("/camera_0/segmentation/calibrate", ros::Duration(20.0)));
  ASSERT_TRUE(ros::service::call("/camera_0/segmentation/calibrate", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  std::uint64_t before = 0;
  double seconds_before = 0;
  {
    std::lock_guard<std::mutex> l(state_->mutex);
    before = state_->blobs;
    seconds_before = state_->blob_seconds;
    state_->blob_seconds_max = 0;
  }
  ros::Rate rate(60.0);
  const int frames = 300;  // 5 s
  for (int i = 0; i < frames; ++i) {
    image_pub_->publish(noise());
    rate.sleep();
  }
  ros::WallDuration(0.5).sleep();
  std::uint64_t blobs = 0;
  double mean_ms = 0, max_ms = 0;
  {
    std::lock_guard<std::mutex> l(state_->mutex);
    blobs = state_->blobs - before;
    mean_ms = blobs ? 1e3 * (state_->blob_seconds - seconds_before) / blobs : 0.0;
    max_ms = 1e3 * state_->blob_seconds_max;
  }
  std::printf(
      "[ noise ] %llu of %d noise frames segmented at 60 Hz; processing time mean %.2f ms, max %.2f ms\n",
      static_cast<unsigned long long>(blobs), frames, mean_ms, max_ms);
  // Frames may be dropped by the subscription queue on a loaded machine, but most arrive.
  EXPECT_GE(blobs, static_cast<std::uint64_t>(frames / 2));
  EXPECT_GT(mean_ms, 0.0);
}

TEST_F(BadInputTest, CameraInfoWithNanOrZeroFocalIsRefusedAndCounted) {
  const soccer_vision::FieldGeometry field;
  sensor_msgs::CameraInfo info =
      soccer_vision::toCameraInfo(soccer_vision::CameraModel::defaultCamera(field, 0), "camera_0_optical");
  for (int i = 0; i < 3; ++i) {
    sensor_msgs::CameraInfo nan = info;
    nan.K[0] = std::nan("");
    info_pub_->publish(nan);
    sensor_msgs::CameraInfo zero = info;
    zero.K[4] = 0;
    info_pub_->publish(zero);
    ros::WallDuration(0.05).sleep();
  }
  EXPECT_GE(
      value("camera_0/identification: identification", "camera_info refused (NaN/Inf, focal <= 0, size)"), 6);
  EXPECT_GE(value("tracking: tracking", "camera_info refused (NaN/Inf, focal <= 0, size)"), 6);
}

TEST_F(BadInputTest, StampsGoingBackAndJumpingResetTheTrackerWithoutPoisoningTf) {
  auto detections = [](double stamp) {
    soccer_vision::CameraDetections d;
    d.header.stamp.fromSec(stamp);
    d.header.frame_id = "field";
    d.camera_id = 0;
    d.global_search = true;
    soccer_vision::RobotPose r;
    r.header = d.header;
    r.team = soccer_vision::RobotPose::TEAM_BLUE;
    r.id = 1;
    r.x = -1.0;
    r.y = 0.5;
    r.theta = 0.3;
    r.confidence = 1.0f;
    r.visible = true;
    d.robots.push_back(r);
    return d;
  };
  const double t0 = ros::Time::now().toSec();
  double t = t0;
  for (int i = 0; i < 30; ++i, t += 1 / 60.0) {
    detections_pub_->publish(detections(t));
    ros::WallDuration(1 / 60.0).sleep();
  }
  detections_pub_->publish(detections(2.2e9));  // one frame stamped in 2039
  ros::WallDuration(1 / 60.0).sleep();
  for (int i = 0; i < 30; ++i, t += 1 / 60.0) {
    detections_pub_->publish(detections(t));
    ros::WallDuration(1 / 60.0).sleep();
  }
  t -= 30.0;  // backwards: a restarted recording
  for (int i = 0; i < 30; ++i, t += 1 / 60.0) {
    detections_pub_->publish(detections(t));
    ros::WallDuration(1 / 60.0).sleep();
  }
  const double resets = value("tracking: tracking", "resets (time jumps)");
  const double held = value("tracking: tracking", "tf held back (unconfirmed stamp jumps)");
  std::uint64_t tf = 0, far = 0;
  {
    std::lock_guard<std::mutex> l(state_->mutex);
    tf = state_->tf;
    far = state_->far_future_tf;
  }
  std::printf("[ stamps ] %g tracker resets, %g tf messages held back, %llu transforms published\n", resets,
              held, static_cast<unsigned long long>(tf));
  EXPECT_GE(resets, 1);
  EXPECT_GE(held, 2) << "the jump to 2039 and the first frame back";
  EXPECT_EQ(far, 0u) << "no transform may carry the isolated far-future stamp";
  EXPECT_GT(tf, 30u);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_bad_input");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
