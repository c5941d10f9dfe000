#include "soccer_vision/sources/images_source.h"

#include <algorithm>
#include <cctype>
#include <dirent.h>
#include <fstream>
#include <iterator>

#include <opencv2/imgcodecs.hpp>
#include <sys/stat.h>

#include "soccer_vision/sources/source_settings.h"

namespace soccer_vision {

namespace {

bool isDirectory(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool hasImageExtension(const std::string& name) {
  const auto dot = name.rfind('.');
  if (dot == std::string::npos) return false;
  std::string ext = name.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const char* kExtensions[] = {"png",  "jpg", "jpeg", "bmp", "tif",
                                      "tiff", "pgm", "ppm",  "pnm", "webp"};
  return std::any_of(std::begin(kExtensions), std::end(kExtensions), [&](const char* e) { return ext == e; });
}

bool readFile(const std::string& path, std::vector<unsigned char>& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !bytes.empty();
}

}  // namespace

std::vector<std::string> listImageFiles(const std::string& folder_or_glob) {
  std::vector<std::string> files;
  if (isDirectory(folder_or_glob)) {
    if (DIR* dir = ::opendir(folder_or_glob.c_str())) {
      const std::string prefix = folder_or_glob.back() == '/' ? folder_or_glob : folder_or_glob + "/";
      while (const dirent* e = ::readdir(dir)) {
        const std::string name = e->d_name;
        if (name.empty() || name[0] == '.' || !hasImageExtension(name)) continue;
        const std::string full = prefix + name;
        if (!isDirectory(full)) files.push_back(full);
      }
      ::closedir(dir);
    }
  } else {
    std::vector<cv::String> matches;
    try {
      cv::glob(folder_or_glob, matches, false);
    } catch (const cv::Exception&) {
      matches.clear();  // a pattern whose folder does not exist matches nothing
    }
    for (const cv::String& m : matches)
      if (!isDirectory(m)) files.push_back(m);
  }
  std::sort(files.begin(), files.end());
  return files;
}

OpenResult ImagesSource::open(const FrameSourceOptions& options) {
  close();
  OpenResult result;
  SettingsReader settings(options.settings);
  const std::string path = settings.text("path");
  const bool realtime = settings.flag("realtime", true);
  const bool loop = settings.flag("loop", false);
  const std::string encoding = settings.text("encoding", "bgr8");
  if (!settings.ok()) {
    result.error = settings.error();
    return result;
  }
  if (path.empty()) {
    result.error = "the images source needs the setting 'path' (a folder or a glob pattern)";
    return result;
  }
  int flags = 0;
  if (encoding == "bgr8") {
    flags = cv::IMREAD_COLOR;
  } else if (encoding == "mono8" || encoding == "bayer_rggb8" || encoding == "bayer_bggr8" ||
             encoding == "bayer_gbrg8" || encoding == "bayer_grbg8") {
    flags = cv::IMREAD_GRAYSCALE;
  } else {
    result.error =
        "images encoding '" + encoding + "' is not supported (bgr8, mono8, bayer_{rggb,bggr,gbrg,grbg}8)";
    return result;
  }
  if (options.fps < 0 || options.fps > 1000) {
    result.error = "fps " + std::to_string(options.fps) + " out of range [0, 1000]";
    return result;
  }
  std::vector<std::string> files = listImageFiles(path);
  if (files.empty()) {
    result.error = isDirectory(path) ? "folder '" + path + "' has no image files"
                                     : "no image files match '" + path + "'";
    return result;
  }
  const cv::Mat first = cv::imread(files.front(), flags);
  if (first.empty()) {
    result.error = "image '" + files.front() + "' cannot be read";
    return result;
  }
  if (encoding.rfind("bayer_", 0) == 0 && (first.cols % 2 != 0 || first.rows % 2 != 0)) {
    result.error = "Bayer image '" + files.front() + "' has an odd size " + std::to_string(first.cols) + "x" +
                   std::to_string(first.rows);
    return result;
  }
  if (options.width > 0 || options.height > 0)
    result.warnings.push_back("the images source does not scale: width/height ignored");

  std::lock_guard<std::mutex> lock(mutex_);
  files_ = std::move(files);
  path_ = path;
  realtime_ = realtime;
  loop_ = loop;
  imread_flags_ = flags;
  format_.width = first.cols;
  format_.height = first.rows;
  format_.encoding = encoding;
  format_.cv_type = first.type();
  format_.step = static_cast<std::size_t>(first.cols) * first.elemSize();
  pacer_.start(realtime ? (options.fps > 0 ? options.fps : kDefaultFps) : 0.0);
  next_ = 0;
  sequence_ = 0;
  loops_ = 0;
  open_ = true;
  result.ok = true;
  return result;
}

void ImagesSource::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  open_ = false;
}

bool ImagesSource::isOpen() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

FrameFormat ImagesSource::format() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_ ? format_ : FrameFormat{};
}

double ImagesSource::fps() const { return pacer_.fps(); }

void ImagesSource::interrupt() { pacer_.interrupt(); }

bool ImagesSource::setFps(double fps, std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  return setPacedFps(pacer_, realtime_, "images", fps, error);
}

std::vector<std::string> ImagesSource::files() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return files_;
}

std::vector<std::pair<std::string, std::string>> ImagesSource::statistics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {{"path", path_},
          {"images", std::to_string(files_.size())},
          {"loops completed", std::to_string(loops_)}};
}

GrabStatus ImagesSource::grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) {
  if (!isOpen()) {
    error = "images source is not open";
    return GrabStatus::Error;
  }
  if (image.data == nullptr || image.rows != format_.height || image.cols != format_.width ||
      image.type() != format_.cv_type) {
    error = "grab() needs a " + std::to_string(format_.width) + "x" + std::to_string(format_.height) + " " +
            format_.encoding + " buffer";
    return GrabStatus::Error;
  }
  if (next_ >= files_.size()) {
    if (!loop_) return GrabStatus::EndOfStream;
    next_ = 0;
    std::lock_guard<std::mutex> lock(mutex_);
    ++loops_;
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
  const std::string& file = files_[next_++];
  const std::uint64_t sequence = sequence_++;  // a skipped file leaves a gap
  std::vector<unsigned char> bytes;
  if (!readFile(file, bytes)) {
    error = "image '" + file + "' cannot be read; skipped";
    return GrabStatus::Error;
  }
  // Decoded into a new image and copied: imdecode leaves a given buffer untouched when it
  // cannot read the header, which would pass the previous frame as this one.
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(bytes, imread_flags_);
  } catch (const cv::Exception&) {
    decoded = cv::Mat();
  }
  if (decoded.empty()) {
    error = "image '" + file + "' cannot be decoded; skipped";
    return GrabStatus::Error;
  }
  if (decoded.size() != image.size() || decoded.type() != image.type()) {
    error = "image '" + file + "' is " + std::to_string(decoded.cols) + "x" + std::to_string(decoded.rows) +
            ", the sequence is " + std::to_string(format_.width) + "x" + std::to_string(format_.height) +
            "; skipped";
    return GrabStatus::Error;
  }
  decoded.copyTo(image);  // same size and type: into the caller's buffer
  info.stamp = stamp;
  info.sequence = sequence;
  info.encoding = format_.encoding;
  return GrabStatus::Ok;
}

}  // namespace soccer_vision
