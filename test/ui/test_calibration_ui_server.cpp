// The calibration UI's HTTP server over a recording backend: routes, token, request checks.
// Listens on 127.0.0.1, on a free port.
#include <atomic>
#include <fstream>

#include <gtest/gtest.h>

// clang-format off
#include "soccer_vision/ui/calibration_ui_server.h"
// After Eigen (through the header above): httplib.h brings <resolv.h>, whose `_res` macro
// breaks Eigen's templates when they come later.
#include <httplib.h>
// clang-format on

namespace soccer_vision {
namespace {

class RecordingBackend : public CalibrationUiBackend {
 public:
  std::atomic<int> changes{0};
  nlohmann::json info() override { return {{"cameras", {{{"id", 0}, {"namespace", "/camera_0"}}}}}; }
  nlohmann::json status() override { return {{"diagnostics", nlohmann::json::array()}}; }
  std::string liveJpeg(int camera) override {
    if (camera != 0) throw UiRequestError(404, "no camera " + std::to_string(camera));
    return "JPEGBYTES";
  }
  std::string frozenJpeg(int) override { throw UiRequestError(409, "no frozen frame"); }
  std::string classificationJpeg(int) override { throw std::runtime_error("unexpected"); }
  nlohmann::json overlay(int, bool frozen) override { return {{"frozen", frozen}}; }
  nlohmann::json freeze(int) override {
    ++changes;
    return {{"stamp", 1.5}};
  }
  nlohmann::json calibrateColors(int, const nlohmann::json& body) override {
    ++changes;
    const ColorSamples s = parseSamplesRequest(body, 640, 480, UiRequestLimits());
    return {{"success", true}, {"classes", s.size()}};
  }
  nlohmann::json solvePose(int, const nlohmann::json&) override { return {}; }
  nlohmann::json savePose(int) override { return {}; }
};

class ServerTest : public ::testing::Test {
 protected:
  // Always on loopback (tests send to 127.0.0.1 only): the read-only policy beyond loopback is
  // UiAccess's, tested in test_ui_access_and_requests.
  void startServer(const std::string& token) {
    CalibrationUiSettings s;
    s.address = "127.0.0.1";
    s.port = 0;
    s.token = token;
    s.www_dir = ::testing::TempDir() + "/sv_ui_www";
    std::system(("mkdir -p " + s.www_dir).c_str());
    std::ofstream(s.www_dir + "/index.html") << "<html>calibration</html>";
    s.limits.max_body_bytes = 4096;
    server = std::make_unique<CalibrationUiServer>(s, backend);
    server->start();
    client = std::make_unique<httplib::Client>("127.0.0.1", server->port());
  }
  httplib::Result post(const std::string& path, const std::string& body, const std::string& token) {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("X-Token", token);
    return client->Post(path.c_str(), headers, body, "application/json");
  }
  static const std::string kSamples;
  RecordingBackend backend;
  std::unique_ptr<CalibrationUiServer> server;
  std::unique_ptr<httplib::Client> client;
};
const std::string ServerTest::kSamples =
    R"({"samples": {"orange": [[[1, 1], [9, 1], [9, 9]]]}, "save": false})";

TEST_F(ServerTest, ServesThePageTheFramesAndTheInfo) {
  startServer("");
  auto page = client->Get("/index.html");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("calibration"), std::string::npos);
  auto frame = client->Get("/api/cameras/0/live.jpg");
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->status, 200);
  EXPECT_EQ(frame->get_header_value("Content-Type"), "image/jpeg");
  EXPECT_EQ(frame->body, "JPEGBYTES");
  auto info = client->Get("/api/info");
  ASSERT_TRUE(info);
  const auto j = nlohmann::json::parse(info->body);
  EXPECT_TRUE(j["changes_enabled"].get<bool>());
  EXPECT_FALSE(j["token_required"].get<bool>());
  auto overlay = client->Get("/api/cameras/0/overlay?frozen=1");
  ASSERT_TRUE(overlay);
  EXPECT_TRUE(nlohmann::json::parse(overlay->body)["frozen"].get<bool>());
}

TEST_F(ServerTest, ErrorsAreJsonWithTheirStatus) {
  startServer("");
  auto unknown_camera = client->Get("/api/cameras/7/live.jpg");
  ASSERT_TRUE(unknown_camera);
  EXPECT_EQ(unknown_camera->status, 404);
  EXPECT_NE(nlohmann::json::parse(unknown_camera->body)["error"].get<std::string>().find("camera 7"),
            std::string::npos);
  auto not_now = client->Get("/api/cameras/0/frozen.jpg");
  ASSERT_TRUE(not_now);
  EXPECT_EQ(not_now->status, 409);
  auto broken = client->Get("/api/cameras/0/classification.jpg");
  ASSERT_TRUE(broken);
  EXPECT_EQ(broken->status, 500);
  auto no_route = client->Get("/api/nothing");
  ASSERT_TRUE(no_route);
  EXPECT_EQ(no_route->status, 404);
  EXPECT_EQ(server->failed(), 3u);  // the backend's answers; the unknown route never reached it
}

TEST_F(ServerTest, ChangesWithoutTheTokenAreRefused) {
  startServer("s3cret");
  for (const std::string& token : {std::string(), std::string("wrong")}) {
    auto r = post("/api/cameras/0/calibrate", kSamples, token);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << token;
    EXPECT_NE(r->body.find("X-Token"), std::string::npos);
  }
  EXPECT_EQ(backend.changes, 0);
  EXPECT_EQ(server->refused(), 2u);
  auto ok = post("/api/cameras/0/calibrate", kSamples, "s3cret");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200) << ok->body;
  EXPECT_EQ(nlohmann::json::parse(ok->body)["classes"], 1);
  EXPECT_EQ(backend.changes, 1);
  // Reading needs no token.
  auto frame = client->Get("/api/cameras/0/live.jpg");
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->status, 200);
}

TEST_F(ServerTest, BadBodiesNeverReachTheBackend) {
  startServer("");
  auto not_json = post("/api/cameras/0/calibrate", "{samples", "");
  ASSERT_TRUE(not_json);
  EXPECT_EQ(not_json->status, 400);
  auto bad_polygon = post("/api/cameras/0/calibrate", R"({"samples": {"orange": [[[1, 1]]]}})", "");
  ASSERT_TRUE(bad_polygon);
  EXPECT_EQ(bad_polygon->status, 400);
  EXPECT_NE(bad_polygon->body.find("samples.orange[0]"), std::string::npos) << bad_polygon->body;
  auto too_big = post("/api/cameras/0/calibrate", std::string(10000, ' '), "");
  ASSERT_TRUE(too_big);
  EXPECT_EQ(too_big->status, 413);
  EXPECT_EQ(backend.changes, 1);  // only the bad polygon got past the JSON check
  auto fine = post("/api/cameras/0/freeze", "", "");
  ASSERT_TRUE(fine);
  EXPECT_EQ(fine->status, 200);
}

TEST_F(ServerTest, APortInUseIsAClearError) {
  startServer("");
  CalibrationUiSettings s;
  s.port = server->port();
  CalibrationUiServer second(s, backend);
  try {
    second.start();
    FAIL() << "bound a port in use";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(s.port)), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace soccer_vision
