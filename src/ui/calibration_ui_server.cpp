#include "soccer_vision/ui/calibration_ui_server.h"

#include <chrono>
#include <functional>
#include <httplib.h>  // after Eigen (through the header above): <resolv.h> defines `_res`
#include <stdexcept>
#include <utility>

namespace soccer_vision {

namespace {

void answerJson(httplib::Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

bool wantsFrozen(const httplib::Request& req) {
  return req.has_param("frozen") && req.get_param_value("frozen") == "1";
}

}  // namespace

CalibrationUiServer::CalibrationUiServer(CalibrationUiSettings settings, CalibrationUiBackend& backend)
    : settings_(std::move(settings)), backend_(backend), access_(settings_.address, settings_.token) {}

CalibrationUiServer::~CalibrationUiServer() { stop(); }

void CalibrationUiServer::start() {
  if (settings_.port < 0 || settings_.port > 65535)
    throw std::runtime_error("ui_port " + std::to_string(settings_.port) + " is not in 0..65535");
  server_ = std::make_unique<httplib::Server>();
  const int threads = std::max(1, settings_.threads);
  server_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  server_->set_payload_max_length(settings_.limits.max_body_bytes);
  server_->set_read_timeout(5, 0);
  server_->set_write_timeout(5, 0);
  // One request per connection: a kept-alive browser connection would hold a pool thread.
  server_->set_keep_alive_max_count(1);
  // SO_REUSEADDR only: httplib's default adds SO_REUSEPORT, with which a second server would
  // share a port in use instead of failing.
  server_->set_socket_options([](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  server_->set_default_headers({{"Cache-Control", "no-store"}, {"X-Content-Type-Options", "nosniff"}});
  if (!settings_.www_dir.empty() && !server_->set_mount_point("/", settings_.www_dir))
    throw std::runtime_error("the UI's page folder " + settings_.www_dir + " does not exist");
  routes();
  if (settings_.port == 0) {
    bound_port_ = server_->bind_to_any_port(settings_.address);
  } else if (server_->bind_to_port(settings_.address, settings_.port)) {
    bound_port_ = settings_.port;
  }
  if (bound_port_ <= 0)
    throw std::runtime_error("cannot listen on " + settings_.address + ":" + std::to_string(settings_.port) +
                             " (in use, or not an address of this machine)");
  thread_ = std::thread([this] { server_->listen_after_bind(); });
  // httplib's stop() does nothing before the loop runs: wait for it, so stop() always ends it.
  for (int i = 0; i < 500 && !server_->is_running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

void CalibrationUiServer::stop() {
  if (server_) server_->stop();
  if (thread_.joinable()) thread_.join();
}

void CalibrationUiServer::routes() {
  httplib::Server& s = *server_;
  // Every handler: count, run, turn errors into JSON answers; nothing escapes to httplib.
  auto guarded = [this](std::function<void(const httplib::Request&, httplib::Response&)> body) {
    return [this, body](const httplib::Request& req, httplib::Response& res) {
      ++requests_;
      try {
        body(req, res);
      } catch (const UiRequestError& e) {
        if (e.status == 403)
          ++refused_;
        else
          ++failed_;
        answerJson(res, e.status, {{"error", e.what()}});
      } catch (const std::exception& e) {
        ++failed_;
        answerJson(res, 500, {{"error", e.what()}});
      }
    };
  };
  // A change: the token (when set) in X-Token, the body as a JSON object.
  auto change = [this, guarded](std::function<nlohmann::json(int, const nlohmann::json&)> action) {
    return guarded([this, action](const httplib::Request& req, httplib::Response& res) {
      if (!access_.changesEnabled()) throw UiRequestError(403, access_.readOnlyReason());
      if (!access_.mayChange(req.get_header_value("X-Token")))
        throw UiRequestError(403, "this change needs the ui_token in the X-Token header");
      const int camera = parseCameraId(req.matches[1]);
      const nlohmann::json body =
          req.body.empty() ? nlohmann::json::object() : parseJsonBody(req.body, settings_.limits);
      answerJson(res, 200, action(camera, body));
    });
  };
  auto jpeg = [guarded](std::function<std::string(int)> get) {
    return guarded([get](const httplib::Request& req, httplib::Response& res) {
      res.set_content(get(parseCameraId(req.matches[1])), "image/jpeg");
    });
  };

  s.Get("/api/info", guarded([this](const httplib::Request&, httplib::Response& res) {
          nlohmann::json info = backend_.info();
          info["changes_enabled"] = access_.changesEnabled();
          info["token_required"] = access_.tokenRequired();
          info["read_only_reason"] = access_.readOnlyReason();
          answerJson(res, 200, info);
        }));
  s.Get("/api/status", guarded([this](const httplib::Request&, httplib::Response& res) {
          nlohmann::json status = backend_.status();
          status["ui"] = {
              {"requests", requests_.load()}, {"refused", refused_.load()}, {"failed", failed_.load()}};
          answerJson(res, 200, status);
        }));
  s.Get(R"(/api/cameras/([^/]+)/live\.jpg)", jpeg([this](int c) { return backend_.liveJpeg(c); }));
  s.Get(R"(/api/cameras/([^/]+)/frozen\.jpg)", jpeg([this](int c) { return backend_.frozenJpeg(c); }));
  s.Get(R"(/api/cameras/([^/]+)/classification\.jpg)",
        jpeg([this](int c) { return backend_.classificationJpeg(c); }));
  s.Get(R"(/api/cameras/([^/]+)/overlay)",
        guarded([this](const httplib::Request& req, httplib::Response& res) {
          answerJson(res, 200, backend_.overlay(parseCameraId(req.matches[1]), wantsFrozen(req)));
        }));
  s.Post(R"(/api/cameras/([^/]+)/freeze)",
         change([this](int c, const nlohmann::json&) { return backend_.freeze(c); }));
  s.Post(R"(/api/cameras/([^/]+)/calibrate)",
         change([this](int c, const nlohmann::json& body) { return backend_.calibrateColors(c, body); }));
  s.Post(R"(/api/cameras/([^/]+)/pose/solve)",
         change([this](int c, const nlohmann::json& body) { return backend_.solvePose(c, body); }));
  s.Post(R"(/api/cameras/([^/]+)/pose/save)",
         change([this](int c, const nlohmann::json&) { return backend_.savePose(c); }));
  s.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    // Called for every error status: only a route that does not exist has no answer yet.
    if (res.status == 404 && res.body.empty() && req.path.rfind("/api/", 0) == 0)
      answerJson(res, 404, {{"error", "no such request"}});
  });
}

}  // namespace soccer_vision
