#include "soccer_vision/sources/v4l2_formats.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <tuple>

#include <linux/videodev2.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace soccer_vision {

namespace {

struct NamedFormat {
  const char* name;
  std::uint32_t fourcc;
};

constexpr NamedFormat kNames[] = {
    {"YUYV", V4L2_PIX_FMT_YUYV},          {"UYVY", V4L2_PIX_FMT_UYVY},
    {"MJPG", V4L2_PIX_FMT_MJPEG},         {"MJPEG", V4L2_PIX_FMT_MJPEG},
    {"JPEG", V4L2_PIX_FMT_JPEG},          {"RGB3", V4L2_PIX_FMT_RGB24},
    {"RGB", V4L2_PIX_FMT_RGB24},          {"RGB8", V4L2_PIX_FMT_RGB24},
    {"BGR3", V4L2_PIX_FMT_BGR24},         {"BGR", V4L2_PIX_FMT_BGR24},
    {"BGR8", V4L2_PIX_FMT_BGR24},         {"GREY", V4L2_PIX_FMT_GREY},
    {"MONO", V4L2_PIX_FMT_GREY},          {"MONO8", V4L2_PIX_FMT_GREY},
    {"RGGB", V4L2_PIX_FMT_SRGGB8},        {"BAYER_RGGB8", V4L2_PIX_FMT_SRGGB8},
    {"BA81", V4L2_PIX_FMT_SBGGR8},        {"BGGR", V4L2_PIX_FMT_SBGGR8},
    {"BAYER_BGGR8", V4L2_PIX_FMT_SBGGR8}, {"GBRG", V4L2_PIX_FMT_SGBRG8},
    {"BAYER_GBRG8", V4L2_PIX_FMT_SGBRG8}, {"GRBG", V4L2_PIX_FMT_SGRBG8},
    {"BAYER_GRBG8", V4L2_PIX_FMT_SGRBG8},
};

// Lower is preferred.
int preference(std::uint32_t fourcc) {
  switch (fourcc) {
    case V4L2_PIX_FMT_SRGGB8:
    case V4L2_PIX_FMT_SBGGR8:
    case V4L2_PIX_FMT_SGBRG8:
    case V4L2_PIX_FMT_SGRBG8:
      return 0;
    case V4L2_PIX_FMT_RGB24:
    case V4L2_PIX_FMT_BGR24:
      return 1;
    case V4L2_PIX_FMT_YUYV:
    case V4L2_PIX_FMT_UYVY:
      return 2;
    case V4L2_PIX_FMT_MJPEG:
    case V4L2_PIX_FMT_JPEG:
      return 3;
    case V4L2_PIX_FMT_GREY:
      return 4;
  }
  return 100;
}

bool copyRows(const std::uint8_t* data, std::size_t bytes, int height, std::size_t row_bytes,
              std::size_t bytes_per_line, cv::Mat& dst) {
  if (bytes_per_line < row_bytes || bytes < bytes_per_line * static_cast<std::size_t>(height - 1) + row_bytes)
    return false;
  for (int y = 0; y < height; ++y)
    std::copy_n(data + static_cast<std::size_t>(y) * bytes_per_line, row_bytes, dst.ptr(y));
  return true;
}

}  // namespace

std::optional<std::uint32_t> v4l2FourccFromName(const std::string& name, std::string& error) {
  std::string upper = name;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
  for (const NamedFormat& f : kNames)
    if (upper == f.name) return f.fourcc;
  error =
      "unknown V4L2 pixel format '" + name + "' (YUYV, UYVY, MJPG, RGB3, BGR3, GREY, RGGB, BA81, GBRG, GRBG)";
  return std::nullopt;
}

std::string v4l2FourccName(std::uint32_t fourcc) {
  std::string s(4, ' ');
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((fourcc >> (8 * i)) & 0xff);
    s[i] = std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  }
  return s;
}

std::string v4l2Encoding(std::uint32_t fourcc) {
  switch (fourcc) {
    case V4L2_PIX_FMT_YUYV:
    case V4L2_PIX_FMT_UYVY:
    case V4L2_PIX_FMT_MJPEG:
    case V4L2_PIX_FMT_JPEG:
    case V4L2_PIX_FMT_RGB24:
    case V4L2_PIX_FMT_BGR24:
      return "bgr8";
    case V4L2_PIX_FMT_GREY:
      return "mono8";
    case V4L2_PIX_FMT_SRGGB8:
      return "bayer_rggb8";
    case V4L2_PIX_FMT_SBGGR8:
      return "bayer_bggr8";
    case V4L2_PIX_FMT_SGBRG8:
      return "bayer_gbrg8";
    case V4L2_PIX_FMT_SGRBG8:
      return "bayer_grbg8";
  }
  return "";
}

bool negotiateV4l2Format(const std::vector<V4l2Mode>& modes, const V4l2Request& request, V4l2Choice& choice,
                         std::string& error) {
  using Score = std::tuple<int, int, int, double, double>;
  std::optional<Score> best;
  std::string offered;
  for (const V4l2Mode& m : modes) {
    if (v4l2Encoding(m.fourcc).empty() || m.width <= 0 || m.height <= 0) continue;
    if (offered.find(v4l2FourccName(m.fourcc)) == std::string::npos)
      offered += (offered.empty() ? "" : ", ") + v4l2FourccName(m.fourcc);
    if (request.fourcc && m.fourcc != *request.fourcc) continue;
    const bool size_asked = request.width > 0 && request.height > 0;
    const int size_miss = size_asked && (m.width != request.width || m.height != request.height);
    const double size_cost = size_asked
                                 ? std::abs(m.width - request.width) + std::abs(m.height - request.height)
                                 : -static_cast<double>(m.width) * m.height;
    // The mode's rate for this request: the listed one nearest above the request (or the
    // nearest below if none is above); the fastest when no rate is asked for.
    double fps = 0;
    if (!m.fps.empty()) {
      if (request.fps > 0) {
        double above = std::numeric_limits<double>::infinity(), below = 0;
        for (double f : m.fps) {
          if (f >= request.fps - 1e-6)
            above = std::min(above, f);
          else
            below = std::max(below, f);
        }
        fps = std::isfinite(above) ? above : below;
      } else {
        fps = *std::max_element(m.fps.begin(), m.fps.end());
      }
    } else {
      fps = request.fps;  // unknown: ask for it
    }
    const int rate_short = request.fps > 0 && !m.fps.empty() && fps < request.fps - 1e-6;
    const double rate_cost = request.fps > 0 ? std::abs(fps - request.fps) : -fps;
    const Score score{size_miss, rate_short, preference(m.fourcc), size_cost, rate_cost};
    if (!best || score < *best) {
      best = score;
      choice = V4l2Choice{m.fourcc, m.width, m.height, fps};
    }
  }
  if (!best) {
    if (offered.empty())
      error =
          "the device offers no supported pixel format (YUYV, UYVY, MJPG, RGB3, BGR3, "
          "GREY, 8-bit Bayer)";
    else
      error = "the device does not offer " + v4l2FourccName(*request.fourcc) + " (it offers " + offered + ")";
    return false;
  }
  return true;
}

bool convertV4l2Frame(std::uint32_t fourcc, const std::uint8_t* data, std::size_t bytes, int width,
                      int height, std::size_t bytes_per_line, cv::Mat& dst, std::string& error) {
  const std::string encoding = v4l2Encoding(fourcc);
  if (encoding.empty()) {
    error = "pixel format " + v4l2FourccName(fourcc) + " is not supported";
    return false;
  }
  const int type = encoding == "bgr8" ? CV_8UC3 : CV_8UC1;
  if (dst.rows != height || dst.cols != width || dst.type() != type || data == nullptr) {
    error = "frame buffer does not match the negotiated format";
    return false;
  }
  const std::size_t w = static_cast<std::size_t>(width);
  auto truncated = [&] {
    error = v4l2FourccName(fourcc) + " frame truncated: " + std::to_string(bytes) + " bytes";
    return false;
  };
  uchar* const before = dst.data;
  switch (fourcc) {
    case V4L2_PIX_FMT_YUYV:
    case V4L2_PIX_FMT_UYVY: {
      if (width % 2 != 0) {
        error = "YUV 4:2:2 needs an even width";
        return false;
      }
      if (bytes_per_line < 2 * w || bytes < bytes_per_line * (height - 1) + 2 * w) return truncated();
      const cv::Mat src(height, width, CV_8UC2, const_cast<std::uint8_t*>(data), bytes_per_line);
      cv::cvtColor(src, dst, fourcc == V4L2_PIX_FMT_YUYV ? cv::COLOR_YUV2BGR_YUYV : cv::COLOR_YUV2BGR_UYVY);
      break;
    }
    case V4L2_PIX_FMT_RGB24: {
      if (bytes_per_line < 3 * w || bytes < bytes_per_line * (height - 1) + 3 * w) return truncated();
      const cv::Mat src(height, width, CV_8UC3, const_cast<std::uint8_t*>(data), bytes_per_line);
      cv::cvtColor(src, dst, cv::COLOR_RGB2BGR);
      break;
    }
    case V4L2_PIX_FMT_BGR24:
      if (!copyRows(data, bytes, height, 3 * w, bytes_per_line, dst)) return truncated();
      break;
    case V4L2_PIX_FMT_MJPEG:
    case V4L2_PIX_FMT_JPEG: {
      // Decoded into a new image and copied: imdecode leaves a given buffer untouched when
      // it cannot even read the header, which would pass a stale frame as a good one.
      const cv::Mat jpeg(1, static_cast<int>(bytes), CV_8UC1, const_cast<std::uint8_t*>(data));
      cv::Mat decoded;
      try {
        decoded = cv::imdecode(jpeg, cv::IMREAD_COLOR);
      } catch (const cv::Exception&) {
        decoded = cv::Mat();
      }
      if (decoded.empty()) {
        error = "corrupt MJPEG frame (" + std::to_string(bytes) + " bytes)";
        return false;
      }
      if (decoded.cols != width || decoded.rows != height) {
        error = "MJPEG frame is " + std::to_string(decoded.cols) + "x" + std::to_string(decoded.rows) +
                ", not the negotiated " + std::to_string(width) + "x" + std::to_string(height);
        return false;
      }
      decoded.copyTo(dst);
      break;
    }
    default:  // GREY and 8-bit Bayer: published as they are
      if (!copyRows(data, bytes, height, w, bytes_per_line, dst)) return truncated();
  }
  if (dst.data != before) {
    error = "conversion reallocated the frame buffer";
    return false;
  }
  return true;
}

}  // namespace soccer_vision
