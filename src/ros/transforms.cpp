#include "soccer_vision/ros/transforms.h"

#include <cmath>

namespace soccer_vision {

geometry_msgs::TransformStamped toTransformStamped(const Eigen::Isometry3d& parent_T_child,
                                                   const std::string& parent, const std::string& child,
                                                   const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  const Eigen::Vector3d p = parent_T_child.translation();
  const Eigen::Quaterniond q(parent_T_child.rotation());
  t.transform.translation.x = p.x();
  t.transform.translation.y = p.y();
  t.transform.translation.z = p.z();
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

Eigen::Isometry3d fromTransform(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  pose.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z)
                      .normalized()
                      .toRotationMatrix();
  return pose;
}

geometry_msgs::TransformStamped planarTransform(double x, double y, double z, double yaw,
                                                const std::string& parent, const std::string& child,
                                                const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = x;
  t.transform.translation.y = y;
  t.transform.translation.z = z;
  t.transform.rotation.z = std::sin(yaw / 2);
  t.transform.rotation.w = std::cos(yaw / 2);
  return t;
}

std::shared_ptr<SharedStaticTf> SharedStaticTf::get() {
  static std::mutex m;
  static std::weak_ptr<SharedStaticTf> instance;
  std::lock_guard<std::mutex> lock(m);
  std::shared_ptr<SharedStaticTf> p = instance.lock();
  if (!p) {
    p = std::make_shared<SharedStaticTf>();
    instance = p;
  }
  return p;
}

void SharedStaticTf::send(const geometry_msgs::TransformStamped& t) {
  std::lock_guard<std::mutex> lock(mutex_);
  broadcaster_.sendTransform(t);
}

}  // namespace soccer_vision
