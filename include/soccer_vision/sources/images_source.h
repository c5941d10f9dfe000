// The `images` frame source: a folder or a glob pattern of image files, in name order, at a
// given rate; each file is decoded and copied into the caller's buffer.
//
// Settings: path (required: a folder, whose image files .png .jpg .jpeg .bmp .tif .tiff .pgm
// .ppm .pnm .webp are used, or a glob pattern such as /data/run1/frame_*.png); realtime
// (bool, true: paced at options.fps, 10 Hz when 0; false: as fast as the consumer takes
// them); loop (bool, false); encoding (bgr8 default; mono8 or bayer_{rggb,bggr,gbrg,grbg}8
// read the files as single-channel raw frames, e.g. Bayer captures saved as PNG).
// Every image must have the size of the first one; another size is an error for that frame.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "soccer_vision/sources/frame_pacer.h"
#include "soccer_vision/sources/frame_source.h"

namespace soccer_vision {

// Image files of a folder (by extension) or matching a glob pattern, sorted by name.
std::vector<std::string> listImageFiles(const std::string& folder_or_glob);

class ImagesSource : public FrameSource {
 public:
  static constexpr double kDefaultFps = 10.0;

  std::string name() const override { return "images"; }
  OpenResult open(const FrameSourceOptions& options) override;
  void close() override;
  bool isOpen() const override;
  FrameFormat format() const override;
  double fps() const override;
  GrabStatus grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) override;
  void interrupt() override;
  bool setFps(double fps, std::string& error) override;
  std::vector<std::pair<std::string, std::string>> statistics() const override;

  std::vector<std::string> files() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> files_;
  std::string path_;
  bool open_ = false;
  bool realtime_ = true;
  bool loop_ = false;
  int imread_flags_ = 0;
  FrameFormat format_;
  FramePacer pacer_;
  std::size_t next_ = 0;
  std::uint64_t sequence_ = 0;
  std::uint64_t loops_ = 0;
};

}  // namespace soccer_vision
