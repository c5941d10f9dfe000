#include "soccer_vision/sources/aravis_source.h"

extern "C" {
#include <arv.h>
}

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <sstream>

#include "soccer_vision/sources/frame_pacer.h"
#include "soccer_vision/sources/source_settings.h"

namespace soccer_vision {

namespace {

struct PixelFormatName {
  const char* genicam;
  const char* encoding;
};
constexpr PixelFormatName kPixelFormats[] = {
    {"Mono8", "mono8"},
    {"Mono16", "mono16"},
    {"RGB8", "rgb8"},
    {"RGB8Packed", "rgb8"},
    {"BGR8", "bgr8"},
    {"BGR8Packed", "bgr8"},
    {"BayerRG8", "bayer_rggb8"},
    {"BayerBG8", "bayer_bggr8"},
    {"BayerGB8", "bayer_gbrg8"},
    {"BayerGR8", "bayer_grbg8"},
    {"BayerRG16", "bayer_rggb16"},
    {"BayerBG16", "bayer_bggr16"},
    {"BayerGB16", "bayer_gbrg16"},
    {"BayerGR16", "bayer_grbg16"},
};

// Takes ownership of a GError: its message, or `fallback`.
std::string takeError(GError*& e, const std::string& fallback = "unknown error") {
  std::string m = e && e->message ? e->message : fallback;
  g_clear_error(&e);
  return m;
}

const char* bufferStatusName(ArvBufferStatus s) {
  switch (s) {
    case ARV_BUFFER_STATUS_SUCCESS:
      return "success";
    case ARV_BUFFER_STATUS_CLEARED:
      return "cleared";
    case ARV_BUFFER_STATUS_TIMEOUT:
      return "timeout";
    case ARV_BUFFER_STATUS_MISSING_PACKETS:
      return "missing packets";
    case ARV_BUFFER_STATUS_WRONG_PACKET_ID:
      return "wrong packet id";
    case ARV_BUFFER_STATUS_SIZE_MISMATCH:
      return "size mismatch (packet_size?)";
    case ARV_BUFFER_STATUS_FILLING:
      return "filling";
    case ARV_BUFFER_STATUS_ABORTED:
      return "aborted";
    default:
      return "failed";
  }
}

}  // namespace

std::string encodingForGenicamPixelFormat(const std::string& pixel_format) {
  for (const PixelFormatName& p : kPixelFormats)
    if (pixel_format == p.genicam) return p.encoding;
  return "";
}

double DeviceClockMapper::map(double device_s, double receive_s) {
  const double offset = receive_s - device_s;
  if (!offsets_.empty()) {
    const double best = *std::min_element(offsets_.begin(), offsets_.end());
    if (std::abs(offset - best) > reset_s_) offsets_.clear();
  }
  offsets_.push_back(offset);
  if (offsets_.size() > window_) offsets_.erase(offsets_.begin());
  return device_s + *std::min_element(offsets_.begin(), offsets_.end());
}

struct AravisSource::Impl {
  // Capture thread only.
  ArvCamera* camera = nullptr;
  ArvStream* stream = nullptr;
  gulong lost_handler = 0;
  std::string pixel_format;
  std::size_t row_bytes = 0;
  double stamp_delay = 0;
  double frame_timeout = 5;
  double last_frame_time = 0;
  bool have_frame_id = false;
  guint64 last_frame_id = 0;
  DeviceClockMapper clock;

  std::atomic<bool> control_lost{false};
  bool unresponsive = false;  // no frame for frame_timeout: do not wait for its replies
  std::atomic<bool> interrupted{false};

  mutable std::mutex mutex;  // guards everything below
  bool open = false;
  FrameFormat format;
  double fps = 0;
  std::optional<double> pending_fps;
  std::map<std::string, double> pending_controls;
  std::map<std::string, double> control_values;  // read back from the camera
  std::map<std::string, std::pair<double, double>> control_bounds;
  std::string camera_id, model;
  int packet_size = 0;
  std::uint64_t sequence = 0;
  guint64 completed = 0, failures = 0, underruns = 0;
  std::uint64_t incomplete = 0, lost_count = 0;
  std::string last_apply_error;

  static void onControlLost(ArvDevice*, gpointer self) { static_cast<Impl*>(self)->control_lost = true; }

  void release() {
    if (camera && stream && !control_lost && !unresponsive) arv_camera_stop_acquisition(camera, nullptr);
    if (stream) {
      g_object_unref(stream);
      stream = nullptr;
    }
    if (camera) {
      if (lost_handler) g_signal_handler_disconnect(arv_camera_get_device(camera), lost_handler);
      g_object_unref(camera);
      camera = nullptr;
    }
    lost_handler = 0;
  }

  void readBack() {  // capture thread
    std::map<std::string, double> values;
    if (arv_camera_is_exposure_time_available(camera, nullptr)) {
      GError* e = nullptr;
      const double v = arv_camera_get_exposure_time(camera, &e);
      if (!e) values["exposure"] = v;
      g_clear_error(&e);
    }
    if (arv_camera_is_gain_available(camera, nullptr)) {
      GError* e = nullptr;
      const double v = arv_camera_get_gain(camera, &e);
      if (!e) values["gain"] = v;
      g_clear_error(&e);
    }
    double rate = 0;
    if (arv_camera_is_frame_rate_available(camera, nullptr)) {
      GError* e = nullptr;
      rate = arv_camera_get_frame_rate(camera, &e);
      if (e) rate = 0;
      g_clear_error(&e);
    }
    std::lock_guard<std::mutex> lock(mutex);
    control_values = values;
    fps = rate;
  }

  // Applies settings queued by other threads (capture thread). False with `error` if any
  // was refused by the camera.
  bool applyPending(std::string& error) {
    std::optional<double> new_fps;
    std::map<std::string, double> controls;
    {
      std::lock_guard<std::mutex> lock(mutex);
      new_fps.swap(pending_fps);
      controls.swap(pending_controls);
    }
    if (!new_fps && controls.empty()) return true;
    std::string problems;
    GError* e = nullptr;
    if (new_fps) {
      arv_camera_set_frame_rate(camera, *new_fps, &e);
      if (e) problems += "frame rate: " + takeError(e) + "; ";
    }
    for (const auto& [name, value] : controls) {
      if (control_lost) break;
      if (name == "exposure") {
        if (arv_camera_is_exposure_auto_available(camera, nullptr))
          arv_camera_set_exposure_time_auto(camera, ARV_AUTO_OFF, nullptr);
        arv_camera_set_exposure_time(camera, value, &e);
      } else if (name == "gain") {
        if (arv_camera_is_gain_auto_available(camera, nullptr))
          arv_camera_set_gain_auto(camera, ARV_AUTO_OFF, nullptr);
        arv_camera_set_gain(camera, value, &e);
      }
      if (e) problems += name + ": " + takeError(e) + "; ";
    }
    // A refused setting keeps the last read-back values (and a camera that stopped
    // answering is not asked again: each register read would wait for its time-out).
    if (problems.empty()) {
      readBack();
      return true;
    }
    error = "camera refused " + problems.substr(0, problems.size() - 2);
    return false;
  }
};

AravisSource::AravisSource() : impl_(std::make_unique<Impl>()) {}

AravisSource::~AravisSource() { close(); }

OpenResult AravisSource::open(const FrameSourceOptions& options) {
  close();
  Impl& d = *impl_;
  OpenResult result;
  SettingsReader settings(options.settings);
  const std::string name = settings.text("camera");
  const std::string pixel_format = settings.text("pixel_format");
  const int packet_size = static_cast<int>(settings.number("packet_size", 0));
  const int buffers = static_cast<int>(settings.number("buffers", 8));
  d.stamp_delay = settings.number("stamp_delay", 0.0);
  d.frame_timeout = settings.number("frame_timeout", 5.0);
  if (!settings.ok()) {
    result.error = settings.error();
    return result;
  }
  if (buffers < 2 || buffers > 64) {
    result.error = "setting buffers = " + std::to_string(buffers) + " out of range [2, 64]";
    return result;
  }
  if (options.fps < 0 || options.width < 0 || options.height < 0) {
    result.error = "fps, width and height must be >= 0";
    return result;
  }
  const std::string label = name.empty() ? "first Aravis camera" : "Aravis camera '" + name + "'";
  auto fail = [&](const std::string& e) {
    result.error = label + ": " + e;
    d.release();
    return result;
  };

  GError* e = nullptr;
  // Discovery broadcasts on every network interface: only when no camera is named (an IP
  // address is opened directly; another name is looked up by Aravis itself).
  if (name.empty()) {
    arv_update_device_list();
    if (arv_get_n_devices() == 0) {
      result.error = "no Aravis camera found (GigE Vision on the local networks, USB3 Vision)";
      return result;
    }
  }
  d.control_lost = false;
  d.unresponsive = false;
  d.camera = arv_camera_new(name.empty() ? nullptr : name.c_str(), &e);
  if (!d.camera) return fail("not found (" + takeError(e) + ")");
  ArvDevice* device = arv_camera_get_device(d.camera);
  d.lost_handler = g_signal_connect(device, "control-lost", G_CALLBACK(&Impl::onControlLost), &d);

  arv_camera_stop_acquisition(d.camera, nullptr);  // a previous run may have left it running
  arv_camera_set_acquisition_mode(d.camera, ARV_ACQUISITION_MODE_CONTINUOUS, &e);
  if (e) return fail("cannot set continuous acquisition (" + takeError(e) + ")");

  if (!pixel_format.empty()) {
    arv_camera_set_pixel_format_from_string(d.camera, pixel_format.c_str(), &e);
    if (e) {
      takeError(e);
      guint n = 0;
      const char** names = arv_camera_dup_available_pixel_formats_as_strings(d.camera, &n, nullptr);
      std::string available;
      for (guint i = 0; names && i < n; ++i)
        available += std::string(available.empty() ? "" : ", ") + names[i];
      g_free(names);
      return fail("pixel format '" + pixel_format + "' not available (camera offers " + available + ")");
    }
  }
  const char* current_format = arv_camera_get_pixel_format_as_string(d.camera, &e);
  if (e || !current_format) return fail("cannot read the pixel format (" + takeError(e) + ")");
  d.pixel_format = current_format;
  const std::string encoding = encodingForGenicamPixelFormat(d.pixel_format);
  if (encoding.empty())
    return fail("pixel format " + d.pixel_format +
                " is not supported (Mono8/16, RGB8, BGR8, Bayer*8/16); set pixel_format");

  if (options.width > 0 || options.height > 0) {
    gint x, y, w, h;
    arv_camera_get_region(d.camera, &x, &y, &w, &h, &e);
    if (e) return fail("cannot read the region (" + takeError(e) + ")");
    arv_camera_set_region(d.camera, 0, 0, options.width > 0 ? options.width : w,
                          options.height > 0 ? options.height : h, &e);
    if (e)
      return fail("region " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                  " refused (" + takeError(e) + ")");
  }
  gint x, y, width, height;
  arv_camera_get_region(d.camera, &x, &y, &width, &height, &e);
  if (e) return fail("cannot read the region (" + takeError(e) + ")");
  if ((options.width > 0 && width != options.width) || (options.height > 0 && height != options.height))
    result.warnings.push_back(label + ": region is " + std::to_string(width) + "x" + std::to_string(height) +
                              ", not the requested " + std::to_string(options.width) + "x" +
                              std::to_string(options.height));

  if (options.fps > 0) {
    if (!arv_camera_is_frame_rate_available(d.camera, nullptr)) {
      result.warnings.push_back(label + " has no frame rate control; fps ignored");
    } else {
      arv_camera_set_frame_rate(d.camera, options.fps, &e);
      if (e)
        result.warnings.push_back(label + ": frame rate " + std::to_string(options.fps) + " Hz refused (" +
                                  takeError(e) + ")");
    }
  }

  int packet = 0;
  if (arv_camera_is_gv_device(d.camera)) {
    if (packet_size > 0)
      arv_camera_gv_set_packet_size(d.camera, packet_size, &e);
    else if (packet_size == 0)
      arv_camera_gv_auto_packet_size(d.camera, &e);
    if (e) result.warnings.push_back(label + ": packet size not set (" + takeError(e) + ")");
    packet = arv_camera_gv_get_packet_size(d.camera, nullptr);
  }

  const guint payload = arv_camera_get_payload(d.camera, &e);
  if (e || payload == 0) return fail("cannot read the payload size (" + takeError(e) + ")");
  d.stream = arv_camera_create_stream(d.camera, nullptr, nullptr, &e);
  if (!d.stream) return fail("cannot create a stream (" + takeError(e) + ")");
  for (int i = 0; i < buffers; ++i) arv_stream_push_buffer(d.stream, arv_buffer_new(payload, nullptr));

  const int cv_type = cvTypeForEncoding(encoding);
  d.row_bytes = static_cast<std::size_t>(width) * CV_ELEM_SIZE(cv_type);
  d.readBack();
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    d.control_bounds.clear();
    double lo = 0, hi = 0;
    if (arv_camera_is_exposure_time_available(d.camera, nullptr)) {
      arv_camera_get_exposure_time_bounds(d.camera, &lo, &hi, nullptr);
      d.control_bounds["exposure"] = {lo, hi};
    }
    if (arv_camera_is_gain_available(d.camera, nullptr)) {
      arv_camera_get_gain_bounds(d.camera, &lo, &hi, nullptr);
      d.control_bounds["gain"] = {lo, hi};
    }
  }
  arv_camera_start_acquisition(d.camera, &e);
  if (e) return fail("cannot start acquisition (" + takeError(e) + ")");

  const char* id = arv_camera_get_device_id(d.camera, nullptr);
  const char* model = arv_camera_get_model_name(d.camera, nullptr);
  d.clock.reset();
  d.have_frame_id = false;
  d.last_frame_time = systemClockNow();
  d.interrupted = false;
  std::lock_guard<std::mutex> lock(d.mutex);
  d.format.width = width;
  d.format.height = height;
  d.format.encoding = encoding;
  d.format.cv_type = cv_type;
  d.format.step = d.row_bytes;
  d.camera_id = id ? id : "";
  d.model = model ? model : "";
  d.packet_size = packet;
  d.pending_fps.reset();
  d.pending_controls.clear();
  d.sequence = 0;
  d.completed = d.failures = d.underruns = 0;
  d.incomplete = 0;
  d.open = true;
  result.ok = true;
  return result;
}

void AravisSource::close() {
  Impl& d = *impl_;
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    if (d.open && d.stream) arv_stream_get_statistics(d.stream, &d.completed, &d.failures, &d.underruns);
    d.open = false;
  }
  d.release();
}

bool AravisSource::isOpen() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->open;
}

FrameFormat AravisSource::format() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->open ? impl_->format : FrameFormat{};
}

double AravisSource::fps() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->fps;
}

void AravisSource::interrupt() { impl_->interrupted = true; }

bool AravisSource::setFps(double fps, std::string& error) {
  if (!(fps > 0) || fps > 10000) {
    error = "fps " + std::to_string(fps) + " out of range (0, 10000]";
    return false;
  }
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->pending_fps = fps;
  return true;
}

std::vector<std::string> AravisSource::controls() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  std::vector<std::string> names;
  for (const auto& kv : impl_->control_bounds) names.push_back(kv.first);
  return names;
}

std::optional<double> AravisSource::control(const std::string& name) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  // The newest value: queued for the next frame, else read back from the camera.
  auto pending = impl_->pending_controls.find(name);
  if (pending != impl_->pending_controls.end()) return pending->second;
  auto it = impl_->control_values.find(name);
  if (it == impl_->control_values.end()) return std::nullopt;
  return it->second;
}

bool AravisSource::setControl(const std::string& name, double value, std::string& error) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  auto it = impl_->control_bounds.find(name);
  if (it == impl_->control_bounds.end()) {
    error = "the aravis camera has no control '" + name + "'";
    return false;
  }
  if (!(value >= it->second.first && value <= it->second.second)) {
    std::ostringstream os;
    os << "control '" << name << "' = " << value << " out of the camera's range [" << it->second.first << ", "
       << it->second.second << "]";
    error = os.str();
    return false;
  }
  impl_->pending_controls[name] = value;
  return true;
}

std::vector<std::pair<std::string, std::string>> AravisSource::statistics() const {
  const Impl& d = *impl_;
  std::lock_guard<std::mutex> lock(d.mutex);
  guint64 completed = d.completed, failures = d.failures, underruns = d.underruns;
  if (d.open && d.stream) arv_stream_get_statistics(d.stream, &completed, &failures, &underruns);
  std::vector<std::pair<std::string, std::string>> s = {
      {"camera", d.camera_id},
      {"model", d.model},
      {"pixel format", d.pixel_format},
      {"stream completed buffers", std::to_string(completed)},
      {"stream failures", std::to_string(failures)},
      {"stream underruns", std::to_string(underruns)},
      {"incomplete frames", std::to_string(d.incomplete)},
      {"control lost", std::to_string(d.lost_count)}};
  if (d.packet_size > 0) s.emplace_back("packet size", std::to_string(d.packet_size));
  if (!d.last_apply_error.empty()) s.emplace_back("last setting error", d.last_apply_error);
  return s;
}

GrabStatus AravisSource::grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) {
  Impl& d = *impl_;
  FrameFormat format;
  {
    std::lock_guard<std::mutex> lock(d.mutex);
    if (!d.open || !d.stream) {
      error = "aravis source is not open";
      return GrabStatus::Error;
    }
    format = d.format;
  }
  if (d.interrupted) return GrabStatus::Interrupted;
  if (image.data == nullptr || image.rows != format.height || image.cols != format.width ||
      image.type() != format.cv_type) {
    error = "grab() needs a " + std::to_string(format.width) + "x" + std::to_string(format.height) + " " +
            format.encoding + " buffer";
    return GrabStatus::Error;
  }
  auto lost = [&] {
    {
      std::lock_guard<std::mutex> lock(d.mutex);
      ++d.lost_count;
    }
    error = "camera " + d.camera_id + ": control lost (unplugged, powered off or unreachable)";
    return GrabStatus::Error;
  };
  if (d.control_lost) return lost();
  std::string apply_error;
  if (!d.applyPending(apply_error)) {
    std::lock_guard<std::mutex> lock(d.mutex);
    d.last_apply_error = apply_error;  // a refused setting does not stop the stream
  }

  // Wait in short slices so that interrupt() and a lost camera are noticed promptly.
  const double deadline = systemClockNow() + std::max(0.0, timeout_s);
  ArvBuffer* buffer = nullptr;
  for (;;) {
    if (d.interrupted) return GrabStatus::Interrupted;
    if (d.control_lost) return lost();
    const double now = systemClockNow();
    const double slice = std::min(0.05, std::max(0.0, deadline - now));
    buffer = arv_stream_timeout_pop_buffer(d.stream, static_cast<guint64>(slice * 1e6));
    if (buffer) break;
    if (systemClockNow() >= deadline) {
      if (d.frame_timeout > 0 && systemClockNow() - d.last_frame_time > d.frame_timeout) {
        std::ostringstream os;
        os << "camera " << d.camera_id << ": no frame for " << d.frame_timeout << " s";
        error = os.str();
        d.unresponsive = true;
        return GrabStatus::Error;
      }
      return GrabStatus::Timeout;
    }
  }
  const double receive = systemClockNow();
  d.last_frame_time = receive;
  const ArvBufferStatus status = arv_buffer_get_status(buffer);
  GrabStatus result = GrabStatus::Ok;
  if (status != ARV_BUFFER_STATUS_SUCCESS) {
    error = "camera " + d.camera_id + ": incomplete frame (" + bufferStatusName(status) + ")";
    std::lock_guard<std::mutex> lock(d.mutex);
    ++d.incomplete;
    result = GrabStatus::Error;
  } else {
    size_t size = 0;
    const auto* data = static_cast<const std::uint8_t*>(arv_buffer_get_image_data(buffer, &size));
    const int bw = arv_buffer_get_image_width(buffer);
    const int bh = arv_buffer_get_image_height(buffer);
    if (bw != format.width || bh != format.height || !data ||
        size < d.row_bytes * static_cast<std::size_t>(format.height)) {
      error = "camera " + d.camera_id + " sent a " + std::to_string(bw) + "x" + std::to_string(bh) +
              " frame of " + std::to_string(size) + " bytes, expected " + std::to_string(format.width) + "x" +
              std::to_string(format.height);
      result = GrabStatus::Error;
    } else {
      for (int r = 0; r < format.height; ++r)
        std::memcpy(image.ptr(r), data + static_cast<std::size_t>(r) * d.row_bytes, d.row_bytes);
      const guint64 device_ns = arv_buffer_get_timestamp(buffer);
      const guint64 system_ns = arv_buffer_get_system_timestamp(buffer);
      const double received = system_ns > 0 ? 1e-9 * static_cast<double>(system_ns) : receive;
      const double stamp =
          device_ns > 0 ? d.clock.map(1e-9 * static_cast<double>(device_ns), received) : received;
      info.stamp = stamp - d.stamp_delay;
      info.encoding = format.encoding;
      // GigE block ids are 16 bit (1..65535): count the gaps ourselves.
      const guint64 id = arv_buffer_get_frame_id(buffer);
      std::uint64_t step = 1;
      if (d.have_frame_id) {
        if (id > d.last_frame_id && id - d.last_frame_id < 1000)
          step = id - d.last_frame_id;
        else if (id < d.last_frame_id && d.last_frame_id > 65000 && id < 1000)
          step = id + 65535 - d.last_frame_id;
      }
      d.have_frame_id = true;
      d.last_frame_id = id;
      std::lock_guard<std::mutex> lock(d.mutex);
      d.sequence += step;
      info.sequence = d.sequence;
    }
  }
  arv_stream_push_buffer(d.stream, buffer);
  return result;
}

}  // namespace soccer_vision
