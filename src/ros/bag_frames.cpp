#include "soccer_vision/ros/bag_frames.h"

#include <algorithm>
#include <regex>
#include <set>
#include <stdexcept>

#include <rosbag/view.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/image_message.h"

namespace soccer_vision {

namespace {

const std::string kImageSuffix = "/image_raw";

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Merges one camera's ground truth of an instant into `into`: visible if any camera sees it.
void mergeTruth(FrameRecord& into, const FrameRecord& camera) {
  for (const RobotRecord& r : camera.robots) {
    auto it = std::find_if(into.robots.begin(), into.robots.end(),
                           [&](const RobotRecord& o) { return o.team == r.team && o.id == r.id; });
    if (it == into.robots.end())
      into.robots.push_back(r);
    else
      it->visible = it->visible.value_or(false) || r.visible.value_or(false);
  }
  for (std::size_t k = 0; k < camera.balls.size(); ++k) {
    if (k >= into.balls.size())
      into.balls.push_back(camera.balls[k]);
    else
      into.balls[k].visible =
          into.balls[k].visible.value_or(false) || camera.balls[k].visible.value_or(false);
  }
}

}  // namespace

BagFrames::BagFrames(const std::string& path) : path_(path), bag_(std::make_unique<rosbag::Bag>()) {
  try {
    bag_->open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": cannot read the bag (" + e.what() + ")");
  }
  rosbag::View all(*bag_);
  std::set<std::string> namespaces;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    if (endsWith(c->topic, kImageSuffix) && c->datatype == "sensor_msgs/Image") {
      namespaces.insert(c->topic.substr(0, c->topic.size() - kImageSuffix.size()));
    }
  }
  if (namespaces.empty())
    throw std::runtime_error(path + ": no <camera>/image_raw topic (sensor_msgs/Image)");
  static const std::regex kCameraNumber(".*camera_([0-9]+)$");
  int rank = 0;
  std::set<int> ids;
  for (const std::string& ns : namespaces) {
    BagCamera c;
    c.ns = ns;
    std::smatch m;
    c.id = std::regex_match(ns, m, kCameraNumber) ? std::stoi(m[1]) : rank;
    if (!ids.insert(c.id).second)
      throw std::runtime_error(path + ": two cameras numbered " + std::to_string(c.id));
    ++rank;
    rosbag::View images(*bag_, rosbag::TopicQuery(ns + kImageSuffix));
    c.images = images.size();
    rosbag::View info(*bag_, rosbag::TopicQuery(ns + "/camera_info"));
    for (const rosbag::MessageInstance& m : info) {
      if (const auto msg = m.instantiate<sensor_msgs::CameraInfo>()) {
        c.info = *msg;
        c.has_info = true;
        break;
      }
    }
    cameras_.push_back(c);
  }
}

const BagCamera* BagFrames::camera(int id) const {
  for (const BagCamera& c : cameras_) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

std::size_t BagFrames::forEachImage(const std::vector<int>& camera_ids, const ImageVisitor& visit,
                                    BagImageProblems* problems) const {
  std::vector<std::string> topics;
  std::map<std::string, const BagCamera*> by_topic;
  for (const BagCamera& c : cameras_) {
    if (!camera_ids.empty() && std::find(camera_ids.begin(), camera_ids.end(), c.id) == camera_ids.end())
      continue;
    topics.push_back(c.ns + kImageSuffix);
    by_topic[topics.back()] = &c;
  }
  std::size_t visited = 0;
  rosbag::View view(*bag_, rosbag::TopicQuery(topics));
  for (const rosbag::MessageInstance& m : view) {
    const auto msg = m.instantiate<sensor_msgs::Image>();
    if (!msg) continue;
    const auto layout = pixelLayoutForEncoding(msg->encoding);
    if (!layout) {
      if (problems) ++problems->unsupported_encoding, ++problems->encodings[msg->encoding];
      continue;
    }
    bool truncated = false;
    const cv::Mat image = imageView(*msg, *layout, &truncated);
    if (truncated) {
      if (problems) ++problems->truncated;
      continue;
    }
    visit(*by_topic.at(m.getTopic()), *msg, image, *layout);
    ++visited;
  }
  return visited;
}

std::map<std::size_t, BagFrames::Image> BagFrames::images(int camera_id,
                                                          const std::set<std::size_t>& indices) const {
  std::map<std::size_t, Image> out;
  const BagCamera* c = camera(camera_id);
  if (!c || indices.empty()) return out;
  rosbag::View view(*bag_, rosbag::TopicQuery(c->ns + kImageSuffix));
  std::size_t k = 0;
  for (const rosbag::MessageInstance& m : view) {
    const std::size_t index = k++;
    if (index > *indices.rbegin()) break;
    if (!indices.count(index)) continue;
    const auto msg = m.instantiate<sensor_msgs::Image>();
    if (!msg) continue;
    const std::optional<PixelLayout> layout = pixelLayoutForEncoding(msg->encoding);
    if (!layout.has_value()) continue;
    const cv::Mat view_of_msg = imageView(*msg, layout.value());
    if (view_of_msg.empty()) continue;
    out[index] = Image{view_of_msg.clone(), layout.value()};
  }
  return out;
}

std::vector<FrameRecord> BagFrames::groundTruth() const {
  // Per camera, robots and balls of one stamp arrive as two messages; pair them by stamp.
  std::map<std::pair<std::string, ros::Time>, RobotPoseArray> robots;
  std::map<std::pair<std::string, ros::Time>, BallPoseArray> balls;
  std::vector<std::string> topics;
  for (const BagCamera& c : cameras_) {
    topics.push_back(c.ns + "/ground_truth/robots");
    topics.push_back(c.ns + "/ground_truth/balls");
  }
  rosbag::View view(*bag_, rosbag::TopicQuery(topics));
  for (const rosbag::MessageInstance& m : view) {
    const std::string& topic = m.getTopic();
    const std::string ns = topic.substr(0, topic.find("/ground_truth/"));
    if (const auto r = m.instantiate<RobotPoseArray>())
      robots[{ns, r->header.stamp}] = *r;
    else if (const auto b = m.instantiate<BallPoseArray>())
      balls[{ns, b->header.stamp}] = *b;
  }
  std::map<ros::Time, FrameRecord> merged;
  for (const auto& [key, r] : robots) {
    const auto b = balls.find(key);
    const FrameRecord camera = toFrameRecord(r, b == balls.end() ? BallPoseArray{} : b->second);
    auto [it, fresh] = merged.try_emplace(key.second, camera);
    if (!fresh) mergeTruth(it->second, camera);
  }
  std::vector<FrameRecord> frames;
  frames.reserve(merged.size());
  for (auto& [stamp, f] : merged) {
    f.stamp = stamp.toSec();
    frames.push_back(std::move(f));
  }
  return frames;
}

}  // namespace soccer_vision
