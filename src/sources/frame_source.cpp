#include "soccer_vision/sources/frame_source.h"

#include <mutex>
#include <utility>

#include "soccer_vision/sources/aravis_source.h"
#include "soccer_vision/sources/images_source.h"
#include "soccer_vision/sources/synthetic_source.h"
#include "soccer_vision/sources/v4l2_source.h"
#include "soccer_vision/sources/video_source.h"

namespace soccer_vision {

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, FrameSourceFactory> factories;

  Registry() {
    // Built-in back-ends.
    factories["synthetic"] = [] { return std::make_unique<SyntheticSource>(); };
    factories["video"] = [] { return std::make_unique<VideoSource>(); };
    factories["images"] = [] { return std::make_unique<ImagesSource>(); };
    factories["v4l2"] = [] { return std::make_unique<V4l2Source>(); };
    factories["aravis"] = [] { return std::make_unique<AravisSource>(); };
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

const char* grabStatusName(GrabStatus s) {
  switch (s) {
    case GrabStatus::Ok:
      return "ok";
    case GrabStatus::Timeout:
      return "timeout";
    case GrabStatus::Interrupted:
      return "interrupted";
    case GrabStatus::EndOfStream:
      return "end of stream";
    case GrabStatus::Error:
      return "error";
  }
  return "unknown";
}

std::unique_ptr<FrameSource> createFrameSource(const std::string& name, std::string& error) {
  FrameSourceFactory factory;
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    auto it = r.factories.find(name);
    if (it != r.factories.end()) factory = it->second;
  }
  if (!factory) {
    std::string known;
    for (const std::string& n : frameSourceNames()) known += (known.empty() ? "" : ", ") + n;
    error = "unknown frame source '" + name + "' (known: " + known + ")";
    return nullptr;
  }
  std::unique_ptr<FrameSource> source = factory();
  if (!source) error = "frame source factory '" + name + "' returned no source";
  return source;
}

std::vector<std::string> frameSourceNames() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& kv : r.factories) names.push_back(kv.first);
  return names;  // std::map: already sorted
}

void registerFrameSource(const std::string& name, FrameSourceFactory factory) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.factories[name] = std::move(factory);
}

int cvTypeForEncoding(const std::string& e) {
  if (e == "bgr8" || e == "rgb8") return CV_8UC3;
  if (e == "bgra8" || e == "rgba8") return CV_8UC4;
  if (e == "bgr16" || e == "rgb16") return CV_16UC3;
  if (e == "bgra16" || e == "rgba16") return CV_16UC4;
  if (e == "mono8" || e == "8UC1") return CV_8UC1;
  if (e == "mono16" || e == "16UC1") return CV_16UC1;
  if (e == "yuv422" || e == "uyvy" || e == "yuyv") return CV_8UC2;
  if (e.rfind("bayer_", 0) == 0) {
    if (e.size() > 2 && e.compare(e.size() - 2, 2, "16") == 0) return CV_16UC1;
    if (e.back() == '8') return CV_8UC1;
  }
  return -1;
}

}  // namespace soccer_vision
