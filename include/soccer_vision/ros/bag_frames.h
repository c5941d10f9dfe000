// A recording as the offline evaluation reads it: the cameras of a rosbag (every topic
// <ns>/image_raw with its <ns>/camera_info), their images in recording order as cv::Mat
// views of the messages (no copy), and the ground truth the bag carries
// (<ns>/ground_truth/robots and <ns>/ground_truth/balls, as make_scenario writes them).
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/segmentation/pixel_classifier.h"

namespace soccer_vision {

struct BagCamera {
  int id = 0;              // n of a namespace ".../camera_<n>", else its rank
  std::string ns;          // e.g. "/camera_0"
  std::size_t images = 0;  // image_raw messages
  bool has_info = false;
  sensor_msgs::CameraInfo info;  // the first camera_info
};

// Why an image was not handed on.
struct BagImageProblems {
  std::size_t unsupported_encoding = 0, truncated = 0;
  std::size_t other_format = 0;                  // counted by the caller: not the size / layout it expects
  std::map<std::string, std::size_t> encodings;  // unsupported encodings seen
};

class BagFrames {
 public:
  // Opens the bag and lists its cameras; throws std::runtime_error naming the file when it
  // cannot be read or holds no <ns>/image_raw topic.
  explicit BagFrames(const std::string& path);

  const std::string& path() const { return path_; }
  const std::vector<BagCamera>& cameras() const { return cameras_; }
  const BagCamera* camera(int id) const;

  using ImageVisitor = std::function<void(const BagCamera& camera, const sensor_msgs::Image& msg,
                                          const cv::Mat& image, PixelLayout layout)>;
  // Every image of the given cameras (all when empty) in recording order. Images whose
  // encoding the pipeline cannot read, or whose data is shorter than step x height, are
  // skipped and counted. Returns the number of images visited.
  std::size_t forEachImage(const std::vector<int>& camera_ids, const ImageVisitor& visit,
                           BagImageProblems* problems = nullptr) const;

  struct Image {
    cv::Mat pixels;  // a deep copy
    PixelLayout layout = PixelLayout::Bgr;
  };
  // The images of a camera at these indices in recording order, read in one pass over the
  // bag; an index with no image, or one that cannot be read, is missing from the result.
  std::map<std::size_t, Image> images(int camera_id, const std::set<std::size_t>& indices) const;

  // One FrameRecord per stamp from the ground-truth topics, merged over cameras: an object
  // is visible when any camera sees it. Empty when the bag has no ground truth.
  std::vector<FrameRecord> groundTruth() const;

 private:
  std::string path_;
  std::unique_ptr<rosbag::Bag> bag_;
  std::vector<BagCamera> cameras_;
};

}  // namespace soccer_vision
