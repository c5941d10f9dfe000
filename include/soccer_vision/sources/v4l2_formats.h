// Device-independent parts of the `v4l2` source, as pure functions so that they are tested
// without a camera: pixel format names, format negotiation over what a device offers,
// conversion of one driver buffer into the published image, and the driver's
// CLOCK_MONOTONIC buffer stamps on the wall clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace soccer_vision {

// One frame size of one pixel format a device offers, with its frame rates [Hz] (empty when
// the device lists none: any rate may be asked for through VIDIOC_S_PARM).
struct V4l2Mode {
  std::uint32_t fourcc = 0;
  int width = 0;
  int height = 0;
  std::vector<double> fps;
};

struct V4l2Request {
  std::optional<std::uint32_t> fourcc;  // nullopt: the best format that meets size and rate
  int width = 0, height = 0;            // 0: the largest size
  double fps = 0;                       // 0: the fastest rate
};

struct V4l2Choice {
  std::uint32_t fourcc = 0;
  int width = 0;
  int height = 0;
  double fps = 0;  // 0: the device's default
};

// "YUYV", "MJPG" (also "MJPEG"), "RGB3" ("RGB"), "BGR3" ("BGR"), "GREY" ("MONO"), Bayer
// "RGGB", "BA81" (BGGR), "GBRG", "GRBG", or the ROS names "bayer_rggb8", ... ; case-blind.
// nullopt (and `error` listing the names) for anything else.
std::optional<std::uint32_t> v4l2FourccFromName(const std::string& name, std::string& error);
// Four characters of a fourcc, e.g. "YUYV".
std::string v4l2FourccName(std::uint32_t fourcc);
// The encoding published for frames of this format: YUYV, UYVY, MJPEG, RGB3, BGR3 -> bgr8;
// GREY -> mono8; 8-bit Bayer -> bayer_*8 (published as Bayer, not demosaiced). Empty when
// the format is not supported.
std::string v4l2Encoding(std::uint32_t fourcc);

// Picks a mode: first an exact size match (when a size is asked for), then a rate at or
// above the requested one, then the format preference (the asked-for format only, if any;
// else Bayer > RGB3/BGR3 > YUYV/UYVY > MJPEG > GREY: uncompressed colour first), then the
// nearest (or, unasked, the largest) size, then the rate nearest to the request (or, unasked,
// the fastest). False with `error` when no offered mode is usable.
bool negotiateV4l2Format(const std::vector<V4l2Mode>& modes, const V4l2Request& request, V4l2Choice& choice,
                         std::string& error);

// Converts one driver buffer (`bytes` used, rows `bytes_per_line` apart; MJPEG: one JPEG)
// into `dst`, which must be width x height of v4l2Encoding(fourcc)'s type and is written in
// place. False with `error` for truncated or corrupt frames.
bool convertV4l2Frame(std::uint32_t fourcc, const std::uint8_t* data, std::size_t bytes, int width,
                      int height, std::size_t bytes_per_line, cv::Mat& dst, std::string& error);

// A CLOCK_MONOTONIC time on the wall clock, given both clocks read at one instant.
inline double monotonicToWall(double monotonic, double monotonic_now, double wall_now) {
  return wall_now - (monotonic_now - monotonic);
}

}  // namespace soccer_vision
