#include "soccer_vision/sources/video_source.h"

#include <cmath>

#include <sys/stat.h>

#include "soccer_vision/sources/source_settings.h"

namespace soccer_vision {

namespace {

bool isRegularFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

OpenResult VideoSource::open(const FrameSourceOptions& options) {
  close();
  OpenResult result;
  SettingsReader settings(options.settings);
  const std::string file = settings.text("file");
  const bool realtime = settings.flag("realtime", true);
  const bool loop = settings.flag("loop", false);
  if (!settings.ok()) {
    result.error = settings.error();
    return result;
  }
  if (file.empty()) {
    result.error = "the video source needs the setting 'file' (a video file path)";
    return result;
  }
  if (!isRegularFile(file)) {
    result.error = "video file '" + file + "' does not exist or is not a file";
    return result;
  }
  if (options.fps < 0 || options.fps > 1000) {
    result.error = "fps " + std::to_string(options.fps) + " out of range [0, 1000]";
    return result;
  }
  cv::VideoCapture capture;
  if (!capture.open(file, cv::CAP_FFMPEG)) {
    result.error = "video file '" + file + "' cannot be decoded (OpenCV FFmpeg back-end)";
    return result;
  }
  const int width = static_cast<int>(capture.get(cv::CAP_PROP_FRAME_WIDTH));
  const int height = static_cast<int>(capture.get(cv::CAP_PROP_FRAME_HEIGHT));
  if (width <= 0 || height <= 0) {
    result.error = "video file '" + file + "' has no video stream with a known size";
    return result;
  }
  if (options.width > 0 || options.height > 0)
    result.warnings.push_back(
        "the video source does not scale: width/height ignored, frames "
        "are the file's " +
        std::to_string(width) + "x" + std::to_string(height));
  double file_fps = capture.get(cv::CAP_PROP_FPS);
  if (!std::isfinite(file_fps) || file_fps <= 0 || file_fps > 1000) file_fps = 0;
  double rate = options.fps > 0 ? options.fps : file_fps;
  if (realtime && rate <= 0) {
    rate = 30.0;
    result.warnings.push_back("video file '" + file +
                              "' has no frame rate; playing at 30 Hz "
                              "(set fps)");
  }

  std::lock_guard<std::mutex> lock(mutex_);
  capture_ = std::move(capture);
  file_ = file;
  realtime_ = realtime;
  loop_ = loop;
  file_fps_ = file_fps;
  file_frames_ = static_cast<std::int64_t>(capture_.get(cv::CAP_PROP_FRAME_COUNT));
  format_.width = width;
  format_.height = height;
  format_.encoding = "bgr8";
  format_.cv_type = CV_8UC3;
  format_.step = static_cast<std::size_t>(width) * 3;
  pacer_.start(realtime ? rate : 0.0);
  sequence_ = 0;
  loops_ = 0;
  open_ = true;
  result.ok = true;
  return result;
}

void VideoSource::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  open_ = false;
  capture_.release();
}

bool VideoSource::isOpen() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

FrameFormat VideoSource::format() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_ ? format_ : FrameFormat{};
}

double VideoSource::fps() const { return pacer_.fps(); }

double VideoSource::fileFps() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return file_fps_;
}

void VideoSource::interrupt() { pacer_.interrupt(); }

bool VideoSource::setFps(double fps, std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  return setPacedFps(pacer_, realtime_, "video", fps, error);
}

std::vector<std::pair<std::string, std::string>> VideoSource::statistics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {{"file", file_},
          {"file fps", std::to_string(file_fps_)},
          {"file frames", std::to_string(file_frames_)},
          {"loops completed", std::to_string(loops_)}};
}

bool VideoSource::reopenFile(std::string& error) {
  // Seeking to frame 0 is unreliable for some containers; re-opening always works.
  capture_.release();
  if (!capture_.open(file_, cv::CAP_FFMPEG)) {
    error = "video file '" + file_ + "' cannot be re-opened for the next loop";
    return false;
  }
  return true;
}

GrabStatus VideoSource::grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) {
  if (!isOpen()) {
    error = "video source is not open";
    return GrabStatus::Error;
  }
  if (image.data == nullptr || image.rows != format_.height || image.cols != format_.width ||
      image.type() != format_.cv_type) {
    error = "grab() needs a " + std::to_string(format_.width) + "x" + std::to_string(format_.height) +
            " bgr8 buffer";
    return GrabStatus::Error;
  }
  double stamp = 0;
  switch (pacer_.wait(timeout_s, stamp)) {
    case FramePacer::Wait::Interrupted:
      return GrabStatus::Interrupted;
    case FramePacer::Wait::Timeout:
      return GrabStatus::Timeout;
    case FramePacer::Wait::Due:
      break;
  }
  cv::Mat target = image;  // a header on the caller's buffer; read() fills it in place
  bool got = capture_.read(target);
  if (!got) {
    if (!loop_) return GrabStatus::EndOfStream;
    if (!reopenFile(error)) return GrabStatus::Error;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++loops_;
    }
    target = image;
    got = capture_.read(target);
    if (!got) {
      error = "video file '" + file_ + "' gives no frame after re-opening";
      return GrabStatus::Error;
    }
  }
  if (target.data != image.data) {
    error = "video file '" + file_ + "' changed frame size to " + std::to_string(target.cols) + "x" +
            std::to_string(target.rows) + " (or channels); frame dropped";
    return GrabStatus::Error;
  }
  info.stamp = stamp;
  info.sequence = sequence_++;
  info.encoding = format_.encoding;
  return GrabStatus::Ok;
}

}  // namespace soccer_vision
