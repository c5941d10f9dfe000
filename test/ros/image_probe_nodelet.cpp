// soccer_vision_test/ImageProbe: a test-only nodelet that publishes bgr8 frames and reports
// the address of each frame's pixel buffer, so that a test can compare it with the address
// the Segmentation nodelet in the same manager saw (its ~debug_report_data_pointer): equal
// addresses for the same stamp mean the frame reached the Segmentation without any copy.
//
// Parameters (~): width, height (int, 64 x 48), rate (double, 10 Hz).
// Published (node namespace): image_raw (sensor_msgs/Image, bgr8, image_transport),
//   published_address (std_msgs/UInt64MultiArray: [stamp.sec, stamp.nsec, address]).
#include <cstdint>
#include <memory>

#include <boost/make_shared.hpp>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/UInt64MultiArray.h>

namespace soccer_vision_test {

class ImageProbeNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("width", width_, 64);
    pnh.param("height", height_, 48);
    double rate = 10.0;
    pnh.param("rate", rate, 10.0);
    it_ = std::make_unique<image_transport::ImageTransport>(nh);
    image_pub_ = it_->advertise("image_raw", 5);
    address_pub_ = nh.advertise<std_msgs::UInt64MultiArray>("published_address", 50);
    timer_ = nh.createWallTimer(ros::WallDuration(1.0 / rate),
                                [this](const ros::WallTimerEvent&) { publish(); });
  }

  void publish() {
    auto image = boost::make_shared<sensor_msgs::Image>();
    image->header.stamp = ros::Time::now();
    image->header.seq = seq_++;
    image->header.frame_id = "probe_optical";
    image->width = static_cast<uint32_t>(width_);
    image->height = static_cast<uint32_t>(height_);
    image->encoding = "bgr8";
    image->step = image->width * 3;
    image->data.assign(static_cast<std::size_t>(image->step) * image->height,
                       static_cast<std::uint8_t>(seq_ * 7));
    auto report = boost::make_shared<std_msgs::UInt64MultiArray>();
    report->data = {image->header.stamp.sec, image->header.stamp.nsec,
                    static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(image->data.data()))};
    image_pub_.publish(image);  // never touched after this
    address_pub_.publish(report);
  }

  int width_ = 64, height_ = 48;
  std::uint32_t seq_ = 0;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Publisher image_pub_;
  ros::Publisher address_pub_;
  ros::WallTimer timer_;
};

}  // namespace soccer_vision_test

PLUGINLIB_EXPORT_CLASS(soccer_vision_test::ImageProbeNodelet, nodelet::Nodelet)
