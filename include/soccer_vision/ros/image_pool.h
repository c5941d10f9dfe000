// Image messages that come back for later frames once nobody holds them: a camera driver
// publishes a new 15 MB message per 5-Mpixel frame, and allocating one costs page faults and
// zeroing every byte (a tenth of the manager's time at 2 x 75 Hz). A message is handed out
// again only when the pool holds the one reference left: every subscriber, publisher queue
// and serialisation has released it and none can take it again, so writing into it never
// touches a message someone is reading. One thread only (the capture thread).
#pragma once

#include <cstddef>
#include <vector>

#include <sensor_msgs/Image.h>

namespace soccer_vision {

class ImagePool {
 public:
  explicit ImagePool(std::size_t capacity) : capacity_(capacity) {}

  // A message whose data has `bytes` bytes: a released one of the pool (its old pixels and
  // fields still in it), else a new one, kept while the pool has room. Messages of another
  // size leave the pool (freed once released).
  sensor_msgs::ImagePtr acquire(std::size_t bytes);

  std::size_t size() const { return pool_.size(); }

 private:
  std::size_t capacity_;
  std::vector<sensor_msgs::ImagePtr> pool_;
};

}  // namespace soccer_vision
