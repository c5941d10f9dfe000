// Poses of the core (Eigen) <-> tf messages, and the static-tf broadcaster that every
// nodelet of one process shares.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include <Eigen/Geometry>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <tf2_ros/static_transform_broadcaster.h>

namespace soccer_vision {

geometry_msgs::TransformStamped toTransformStamped(const Eigen::Isometry3d& parent_T_child,
                                                   const std::string& parent, const std::string& child,
                                                   const ros::Time& stamp);
Eigen::Isometry3d fromTransform(const geometry_msgs::Transform& t);
// A planar pose (x, y, heading) at height z.
geometry_msgs::TransformStamped planarTransform(double x, double y, double z, double yaw,
                                                const std::string& parent, const std::string& child,
                                                const ros::Time& stamp);

// One StaticTransformBroadcaster per process, shared by every nodelet of a manager: it
// accumulates all transforms sent through it, so each (latched) send carries them all
// (separate broadcasters of one process would overwrite each other's latched message).
class SharedStaticTf {
 public:
  static std::shared_ptr<SharedStaticTf> get();
  void send(const geometry_msgs::TransformStamped& t);

 private:
  std::mutex mutex_;
  tf2_ros::StaticTransformBroadcaster broadcaster_;
};

}  // namespace soccer_vision
