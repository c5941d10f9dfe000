#include "soccer_vision/ros/image_pool.h"

#include <algorithm>

#include <boost/make_shared.hpp>

namespace soccer_vision {

sensor_msgs::ImagePtr ImagePool::acquire(std::size_t bytes) {
  for (const sensor_msgs::ImagePtr& m : pool_)
    if (m.use_count() == 1 && m->data.size() == bytes) return m;
  pool_.erase(std::remove_if(pool_.begin(), pool_.end(),
                             [&](const sensor_msgs::ImagePtr& m) { return m->data.size() != bytes; }),
              pool_.end());
  auto image = boost::make_shared<sensor_msgs::Image>();
  image->data.resize(bytes);
  if (pool_.size() < capacity_) pool_.push_back(image);
  return image;
}

}  // namespace soccer_vision
