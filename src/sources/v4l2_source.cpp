#include "soccer_vision/sources/v4l2_source.h"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <linux/videodev2.h>
#include <sys/eventfd.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/stat.h>

#include "soccer_vision/sources/source_settings.h"

namespace soccer_vision {

namespace {

int xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do {
    r = ::ioctl(fd, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

std::string errnoText() { return std::strerror(errno); }

double clockSeconds(clockid_t id) {
  timespec ts{};
  ::clock_gettime(id, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

V4l2Source::V4l2Source() : wake_fd_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {}

V4l2Source::~V4l2Source() {
  close();
  if (wake_fd_ >= 0) ::close(wake_fd_);
}

std::vector<V4l2Mode> V4l2Source::enumerateModes(const V4l2Request& request) const {
  std::vector<V4l2Mode> modes;
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; xioctl(fd_, VIDIOC_ENUM_FMT, &desc) == 0; ++desc.index) {
    std::vector<std::pair<int, int>> sizes;
    v4l2_frmsizeenum size{};
    size.pixel_format = desc.pixelformat;
    for (size.index = 0; xioctl(fd_, VIDIOC_ENUM_FRAMESIZES, &size) == 0; ++size.index) {
      if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
        sizes.emplace_back(size.discrete.width, size.discrete.height);
      } else {  // stepwise/continuous: the largest and the requested size (snapped to steps)
        const auto& s = size.stepwise;
        sizes.emplace_back(s.max_width, s.max_height);
        if (request.width > 0 && request.height > 0) {
          auto snap = [](int v, unsigned lo, unsigned hi, unsigned step) {
            v = std::max<int>(lo, std::min<int>(hi, v));
            if (step > 1) v = static_cast<int>(lo + (v - lo) / step * step);
            return v;
          };
          sizes.emplace_back(snap(request.width, s.min_width, s.max_width, s.step_width),
                             snap(request.height, s.min_height, s.max_height, s.step_height));
        }
        break;
      }
    }
    for (const auto& [w, h] : sizes) {
      V4l2Mode mode;
      mode.fourcc = desc.pixelformat;
      mode.width = w;
      mode.height = h;
      v4l2_frmivalenum ival{};
      ival.pixel_format = desc.pixelformat;
      ival.width = static_cast<std::uint32_t>(w);
      ival.height = static_cast<std::uint32_t>(h);
      for (ival.index = 0; xioctl(fd_, VIDIOC_ENUM_FRAMEINTERVALS, &ival) == 0; ++ival.index) {
        if (ival.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
          if (ival.discrete.numerator > 0)
            mode.fps.push_back(static_cast<double>(ival.discrete.denominator) / ival.discrete.numerator);
        } else {
          const auto& s = ival.stepwise;  // fastest and slowest; S_PARM picks in between
          if (s.min.numerator > 0) mode.fps.push_back(double(s.min.denominator) / s.min.numerator);
          if (s.max.numerator > 0) mode.fps.push_back(double(s.max.denominator) / s.max.numerator);
          if (request.fps > 0) mode.fps.push_back(request.fps);
          break;
        }
      }
      modes.push_back(std::move(mode));
    }
  }
  return modes;
}

void V4l2Source::findControls() {
  controls_.clear();
  auto query = [&](const char* name, std::uint32_t id, double scale) {
    v4l2_queryctrl q{};
    q.id = id;
    if (xioctl(fd_, VIDIOC_QUERYCTRL, &q) != 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED)) return;
    controls_[name] = Control{id, scale, q.minimum / scale, q.maximum / scale};
  };
  query("exposure", V4L2_CID_EXPOSURE_ABSOLUTE, 0.01);  // control unit: 100 µs
  query("gain", V4L2_CID_GAIN, 1.0);
}

OpenResult V4l2Source::open(const FrameSourceOptions& options) {
  close();
  OpenResult result;
  SettingsReader settings(options.settings);
  const std::string device = settings.text("device", "/dev/video0");
  const std::string pixel_format = settings.text("pixel_format");
  const int buffers = static_cast<int>(settings.number("buffers", 4));
  const double stamp_delay = settings.number("stamp_delay", 0.0);
  if (!settings.ok()) {
    result.error = settings.error();
    return result;
  }
  if (buffers < 2 || buffers > 32) {
    result.error = "setting buffers = " + std::to_string(buffers) + " out of range [2, 32]";
    return result;
  }
  V4l2Request request;
  request.width = options.width;
  request.height = options.height;
  request.fps = options.fps;
  if (!pixel_format.empty()) {
    request.fourcc = v4l2FourccFromName(pixel_format, result.error);
    if (!request.fourcc) return result;
  }

  struct stat st {};
  if (::stat(device.c_str(), &st) != 0) {
    result.error = "V4L2 device " + device + ": " + errnoText();
    return result;
  }
  if (!S_ISCHR(st.st_mode)) {
    result.error = device + " is not a device (character special file)";
    return result;
  }
  const int fd = ::open(device.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    result.error = "cannot open V4L2 device " + device + ": " + errnoText();
    return result;
  }
  fd_ = fd;
  device_ = device;
  buffer_count_ = buffers;
  stamp_delay_ = stamp_delay;
  auto fail = [&](const std::string& e) {
    result.error = device + ": " + e;
    close();
    return result;
  };

  v4l2_capability cap{};
  if (xioctl(fd_, VIDIOC_QUERYCAP, &cap) != 0)
    return fail("not a V4L2 device (VIDIOC_QUERYCAP: " + errnoText() + ")");
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) return fail("not a video capture device");
  if (!(caps & V4L2_CAP_STREAMING)) return fail("does not support streaming I/O");
  card_ = reinterpret_cast<const char*>(cap.card);
  driver_ = reinterpret_cast<const char*>(cap.driver);

  V4l2Choice choice;
  std::string error;
  if (!negotiateV4l2Format(enumerateModes(request), request, choice, error)) return fail(error);
  if (request.width > 0 && (choice.width != request.width || choice.height != request.height))
    result.warnings.push_back(device + " has no " + std::to_string(request.width) + "x" +
                              std::to_string(request.height) + " " + v4l2FourccName(choice.fourcc) +
                              "; using " + std::to_string(choice.width) + "x" +
                              std::to_string(choice.height));

  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = static_cast<std::uint32_t>(choice.width);
  fmt.fmt.pix.height = static_cast<std::uint32_t>(choice.height);
  fmt.fmt.pix.pixelformat = choice.fourcc;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(fd_, VIDIOC_S_FMT, &fmt) != 0) return fail("VIDIOC_S_FMT: " + errnoText());
  if (fmt.fmt.pix.pixelformat != choice.fourcc)
    return fail("driver replaced " + v4l2FourccName(choice.fourcc) + " by " +
                v4l2FourccName(fmt.fmt.pix.pixelformat));
  fourcc_ = fmt.fmt.pix.pixelformat;
  const std::string encoding = v4l2Encoding(fourcc_);
  bytes_per_line_ = fmt.fmt.pix.bytesperline;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    format_.width = static_cast<int>(fmt.fmt.pix.width);
    format_.height = static_cast<int>(fmt.fmt.pix.height);
    format_.encoding = encoding;
    format_.cv_type = cvTypeForEncoding(encoding);
    format_.step = static_cast<std::size_t>(format_.width) * CV_ELEM_SIZE(format_.cv_type);
    if (bytes_per_line_ == 0)  // compressed formats: no rows in the buffer
      bytes_per_line_ =
          fourcc_ == V4L2_PIX_FMT_YUYV || fourcc_ == V4L2_PIX_FMT_UYVY ? 2 * format_.width : format_.step;
  }
  if (choice.fps > 0 && !applyFps(choice.fps, error))
    result.warnings.push_back(device + ": frame rate " + std::to_string(choice.fps) + " Hz not set (" +
                              error + ")");
  if (choice.fps <= 0) applyFps(0, error);  // reads the current rate back
  findControls();
  if (!startStreaming(error)) return fail(error);

  std::lock_guard<std::mutex> lock(mutex_);
  frames_ = driver_drops_ = errors_ = 0;
  last_driver_sequence_ = -1;
  pending_fps_.reset();
  std::uint64_t stale = 0;  // an interrupt() before this open() no longer applies
  if (wake_fd_ >= 0 && ::read(wake_fd_, &stale, sizeof stale) < 0) stale = 0;
  interrupted_ = false;
  open_ = true;
  result.ok = true;
  return result;
}

bool V4l2Source::applyFps(double fps, std::string& error) {
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (fps > 0) {
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(std::lround(fps * 1000));
    if (xioctl(fd_, VIDIOC_S_PARM, &parm) != 0) {
      error = "VIDIOC_S_PARM: " + errnoText();
      return false;
    }
  }
  parm = v4l2_streamparm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  double actual = 0;
  if (xioctl(fd_, VIDIOC_G_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator > 0)
    actual = static_cast<double>(parm.parm.capture.timeperframe.denominator) /
             parm.parm.capture.timeperframe.numerator;
  std::lock_guard<std::mutex> lock(mutex_);
  fps_ = actual;
  return true;
}

bool V4l2Source::startStreaming(std::string& error) {
  v4l2_requestbuffers req{};
  req.count = static_cast<std::uint32_t>(buffer_count_);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &req) != 0) {
    error = "VIDIOC_REQBUFS (mmap): " + errnoText();
    return false;
  }
  if (req.count < 2) {
    error = "driver granted only " + std::to_string(req.count) + " buffer(s)";
    return false;
  }
  buffers_.assign(req.count, Buffer{});
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &buf) != 0) {
      error = "VIDIOC_QUERYBUF: " + errnoText();
      releaseBuffers();
      return false;
    }
    void* p = ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
    if (p == MAP_FAILED) {
      error = "mmap: " + errnoText();
      releaseBuffers();
      return false;
    }
    buffers_[i] = Buffer{p, buf.length};
    if (xioctl(fd_, VIDIOC_QBUF, &buf) != 0) {
      error = "VIDIOC_QBUF: " + errnoText();
      releaseBuffers();
      return false;
    }
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) != 0) {
    error = "VIDIOC_STREAMON: " + errnoText();
    releaseBuffers();
    return false;
  }
  streaming_ = true;
  return true;
}

void V4l2Source::stopStreaming() {
  if (fd_ >= 0 && streaming_) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);
  }
  streaming_ = false;
  releaseBuffers();
}

void V4l2Source::releaseBuffers() {
  for (Buffer& b : buffers_)
    if (b.start) ::munmap(b.start, b.length);
  buffers_.clear();
  if (fd_ >= 0) {  // frees the driver's buffers so the format may change
    v4l2_requestbuffers req{};
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    xioctl(fd_, VIDIOC_REQBUFS, &req);
  }
}

void V4l2Source::close() {
  stopStreaming();
  std::lock_guard<std::mutex> lock(mutex_);
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  open_ = false;
  controls_.clear();
}

bool V4l2Source::isOpen() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

FrameFormat V4l2Source::format() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_ ? format_ : FrameFormat{};
}

double V4l2Source::fps() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return fps_;
}

void V4l2Source::interrupt() {
  interrupted_ = true;
  const std::uint64_t one = 1;
  if (wake_fd_ >= 0 && ::write(wake_fd_, &one, sizeof one) < 0) {
    // Counter full: a wake-up is pending anyway.
  }
}

bool V4l2Source::setFps(double fps, std::string& error) {
  if (!(fps > 0) || fps > 1000) {
    error = "fps " + std::to_string(fps) + " out of range (0, 1000]";
    return false;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  pending_fps_ = fps;  // applied by the capture thread (streaming restarts)
  return true;
}

std::vector<std::string> V4l2Source::controls() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> names;
  for (const auto& kv : controls_) names.push_back(kv.first);
  return names;
}

std::optional<double> V4l2Source::control(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = controls_.find(name);
  if (it == controls_.end() || fd_ < 0) return std::nullopt;
  v4l2_control c{};
  c.id = it->second.id;
  if (xioctl(fd_, VIDIOC_G_CTRL, &c) != 0) return std::nullopt;
  return c.value / it->second.scale;
}

bool V4l2Source::setControl(const std::string& name, double value, std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = controls_.find(name);
  if (it == controls_.end() || fd_ < 0) return FrameSource::setControl(name, value, error);
  const Control& ctl = it->second;
  if (!(value >= ctl.min && value <= ctl.max)) {
    error = "control '" + name + "' = " + std::to_string(value) + " out of the device's range [" +
            std::to_string(ctl.min) + ", " + std::to_string(ctl.max) + "]";
    return false;
  }
  if (name == "exposure") {  // manual exposure first, or the absolute value is ignored
    v4l2_control mode{};
    mode.id = V4L2_CID_EXPOSURE_AUTO;
    mode.value = V4L2_EXPOSURE_MANUAL;
    xioctl(fd_, VIDIOC_S_CTRL, &mode);
  }
  v4l2_control c{};
  c.id = ctl.id;
  c.value = static_cast<std::int32_t>(std::lround(value * ctl.scale));
  if (xioctl(fd_, VIDIOC_S_CTRL, &c) != 0) {
    error = device_ + ": setting " + name + " failed: " + errnoText();
    return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> V4l2Source::statistics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {{"device", device_},
          {"card", card_},
          {"driver", driver_},
          {"pixel format", v4l2FourccName(fourcc_)},
          {"frames", std::to_string(frames_)},
          {"driver sequence gaps", std::to_string(driver_drops_)},
          {"corrupt frames", std::to_string(errors_)}};
}

GrabStatus V4l2Source::grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) {
  FrameFormat format;
  std::optional<double> new_fps;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!open_) {
      error = "V4L2 source is not open";
      return GrabStatus::Error;
    }
    format = format_;
    new_fps.swap(pending_fps_);
  }
  if (interrupted_) return GrabStatus::Interrupted;
  if (image.data == nullptr || image.rows != format.height || image.cols != format.width ||
      image.type() != format.cv_type) {
    error = "grab() needs a " + std::to_string(format.width) + "x" + std::to_string(format.height) + " " +
            format.encoding + " buffer";
    return GrabStatus::Error;
  }
  if (new_fps) {  // most drivers refuse S_PARM while streaming
    stopStreaming();
    std::string fps_error;
    if (!applyFps(*new_fps, fps_error)) error = fps_error;
    if (!startStreaming(fps_error)) {
      error = fps_error;
      return GrabStatus::Error;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    last_driver_sequence_ = -1;  // the driver counts from 0 again
  }

  pollfd fds[2] = {{fd_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
  const int r = ::poll(fds, wake_fd_ >= 0 ? 2 : 1, static_cast<int>(std::max(0.0, timeout_s) * 1000.0));
  if (interrupted_) return GrabStatus::Interrupted;
  if (r == 0) return GrabStatus::Timeout;
  if (r < 0) {
    if (errno == EINTR) return GrabStatus::Timeout;
    error = device_ + ": poll: " + errnoText();
    return GrabStatus::Error;
  }
  if (fds[0].revents & (POLLERR | POLLHUP | POLLNVAL)) {
    error = device_ + " is gone or failed (poll error)";
    return GrabStatus::Error;
  }

  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &buf) != 0) {
    if (errno == EAGAIN) return GrabStatus::Timeout;
    error = device_ + ": VIDIOC_DQBUF: " + errnoText();  // ENODEV: unplugged
    return GrabStatus::Error;
  }
  const double wall_now = clockSeconds(CLOCK_REALTIME);
  const double mono_now = clockSeconds(CLOCK_MONOTONIC);
  bool ok = true;
  if (buf.flags & V4L2_BUF_FLAG_ERROR) {
    error = device_ + ": the driver marked the frame corrupt";
    ok = false;
  } else if (buf.index >= buffers_.size()) {
    error = device_ + ": driver returned unknown buffer " + std::to_string(buf.index);
    ok = false;
  } else {
    cv::Mat target = image;
    ok = convertV4l2Frame(fourcc_, static_cast<const std::uint8_t*>(buffers_[buf.index].start), buf.bytesused,
                          format.width, format.height, bytes_per_line_, target, error);
  }
  double stamp = wall_now - stamp_delay_;
  const double driver_stamp =
      static_cast<double>(buf.timestamp.tv_sec) + 1e-6 * static_cast<double>(buf.timestamp.tv_usec);
  if ((buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC && driver_stamp > 0) {
    stamp = monotonicToWall(driver_stamp, mono_now, wall_now);
    if ((buf.flags & V4L2_BUF_FLAG_TSTAMP_SRC_MASK) != V4L2_BUF_FLAG_TSTAMP_SRC_SOE)
      stamp -= stamp_delay_;  // end-of-frame stamp
  }
  const std::int64_t driver_sequence = buf.sequence;
  if (xioctl(fd_, VIDIOC_QBUF, &buf) != 0 && ok) {
    error = device_ + ": VIDIOC_QBUF: " + errnoText();
    ok = false;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (!ok) {
    ++errors_;
    return GrabStatus::Error;
  }
  if (last_driver_sequence_ >= 0 && driver_sequence > last_driver_sequence_ + 1)
    driver_drops_ += static_cast<std::uint64_t>(driver_sequence - last_driver_sequence_ - 1);
  last_driver_sequence_ = driver_sequence;
  info.stamp = stamp;
  info.sequence = frames_ + driver_drops_;  // ours: keeps counting across restarts
  info.encoding = format.encoding;
  ++frames_;
  return GrabStatus::Ok;
}

}  // namespace soccer_vision
