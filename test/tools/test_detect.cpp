// detect end to end on a rendered frame (camera 0 of the synthetic field, robots and a ball
// at known places, a colour table calibrated on that frame's sample polygons): every robot
// and the ball within 1 px of their projections, the JSON schema as specified, positions
// null without a pose, bad arguments refused with exit status 2.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sys/wait.h>

#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/common/angle.h"
#include "soccer_vision/common/camera_info_yaml.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/rejection_counts.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "support/scene_objects.h"

using namespace soccer_vision;
using soccer_vision::test::robotState;
using json = nlohmann::json;

namespace {

const std::string kDir = ::testing::TempDir() + "/detect_test";

struct ToolRun {
  int status = -1;
  std::string output;
};

ToolRun run(const std::string& args) {
  const std::string cmd = std::string(DETECT_BIN) + " " + args + " 2>&1";
  ToolRun r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), p)) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

json readJson(const std::string& path) {
  std::ifstream f(path);
  return json::parse(f);
}

std::set<std::string> keys(const json& object) {
  std::set<std::string> out;
  for (const auto& [k, v] : object.items()) out.insert(k);
  return out;
}

class Detect : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_EQ(std::system(("rm -rf " + kDir + " && mkdir -p " + kDir).c_str()), 0);
    scene_.robots = {
        robotState(Team::Blue, 0, -3.5, 1.8, 0.3),    robotState(Team::Blue, 1, -2.0, -0.5, 2.0),
        robotState(Team::Blue, 2, -1.0, 2.2, -1.2),   robotState(Team::Blue, 3, -3.9, -2.4, 3.0),
        robotState(Team::Yellow, 0, -2.6, 0.9, -2.6), robotState(Team::Yellow, 1, -0.8, -1.6, 1.0),
        robotState(Team::Yellow, 2, -3.0, -1.2, 0.0), robotState(Team::Yellow, 4, -1.6, 1.1, -0.4)};
    BallState ball;
    ball.x = -2.3;
    ball.y = -1.9;
    scene_.balls = {ball};
    ScenarioConfig scenario;
    renderer_ = std::make_unique<FieldRenderer>(camera(), field_, patterns_, scenario);
    RenderedFrame frame;
    renderer_->render(scene_, 0, frame);
    ASSERT_TRUE(cv::imwrite(image(), frame.image));
    SampleOptions options;
    options.shrink = 0.85;
    ColorTableParams params;
    params.s_bins = 8;
    params.v_bins = 8;
    calibrateColorTable({{frame.image, calibrationSamples(scene_, camera(), field_, patterns_, options)}},
                        params)
        .save(table());
    saveCameraInfoYaml(cameraInfo(), camera().intrinsics(), "camera_0");
    CameraPoseFile pose;
    pose.field_T_camera = camera().fieldTCamera();
    pose.intrinsics = camera().intrinsics();
    saveCameraPoseFile(cameraPose(), pose);
  }
  static void TearDownTestSuite() { renderer_.reset(); }

  static const CameraModel& camera() {
    static const CameraModel c = CameraModel::defaultCamera(field_, 0);
    return c;
  }
  static std::string image() { return kDir + "/frame.png"; }
  static std::string table() { return kDir + "/table.svct"; }
  static std::string cameraInfo() { return kDir + "/camera_info.yaml"; }
  static std::string cameraPose() { return kDir + "/camera_pose.yaml"; }

  // The robot's centre at marker height and the ball's centre, projected.
  static Eigen::Vector2d pixelOf(const RobotState& r) {
    return *camera().project({r.x, r.y, patterns_.height(r.team)});
  }
  static Eigen::Vector2d pixelOf(const BallState& b) { return *camera().project({b.x, b.y, b.z}); }

  // Every robot of the scene in the JSON once, at its projection; the worst distance [px].
  static double expectEveryRobotAtItsPixel(const json& robots) {
    double worst = 0;
    EXPECT_EQ(robots.size(), scene_.robots.size());
    for (const RobotState& t : scene_.robots) {
      int matches = 0;
      for (const json& r : robots) {
        if (r["team"] != std::string(teamName(t.team)) || r["id"] != t.id) continue;
        ++matches;
        const double d = (Eigen::Vector2d(r["u"].get<double>(), r["v"].get<double>()) - pixelOf(t)).norm();
        worst = std::max(worst, d);
        EXPECT_LT(d, 1.0) << teamName(t.team) << " " << t.id;
      }
      EXPECT_EQ(matches, 1) << teamName(t.team) << " " << t.id;
    }
    return worst;
  }

  static inline const FieldGeometry field_{};
  static inline const PatternSet patterns_ = PatternSet::twoTag();
  static inline SceneState scene_;
  static inline std::unique_ptr<FieldRenderer> renderer_;
};

TEST_F(Detect, FindsEveryRobotAndTheBallAtTheirProjectionsWithAPose) {
  for (const RobotState& r : scene_.robots) ASSERT_TRUE(renderer_->robotVisible(r));
  const std::string out = kDir + "/with_pose.json", overlay = kDir + "/overlay.png";
  const ToolRun r = run("--image " + image() + " --colors " + table() + " --camera-info " + cameraInfo() +
                        " --camera-pose " + cameraPose() + " --json " + out + " --overlay " + overlay);
  ASSERT_EQ(r.status, 0) << r.output;
  std::printf("%s", r.output.c_str());
  const json j = readJson(out);
  EXPECT_EQ(keys(j), (std::set<std::string>{"blobs", "robots", "balls", "rejections", "rejected_robots"}));
  ASSERT_GT(j["blobs"].size(), 2 * scene_.robots.size());
  for (const json& b : j["blobs"]) {
    EXPECT_EQ(keys(b), (std::set<std::string>{"color", "area", "cx", "cy", "box", "sd", "angle"}));
    EXPECT_GE(b["sd"][0].get<double>(), b["sd"][1].get<double>()) << b.dump();
    EXPECT_TRUE(b["color"].is_string());
    EXPECT_GT(b["area"].get<double>(), 0);
    // The centroid lies inside the bounding box.
    ASSERT_EQ(b["box"].size(), 4u);
    EXPECT_GE(b["cx"].get<double>(), b["box"][0].get<double>()) << b.dump();
    EXPECT_LE(b["cx"].get<double>(), b["box"][0].get<double>() + b["box"][2].get<double>()) << b.dump();
    EXPECT_GE(b["cy"].get<double>(), b["box"][1].get<double>()) << b.dump();
    EXPECT_LE(b["cy"].get<double>(), b["box"][1].get<double>() + b["box"][3].get<double>()) << b.dump();
  }
  for (const json& robot : j["robots"]) {
    EXPECT_EQ(keys(robot), (std::set<std::string>{"team", "id", "x", "y", "theta", "u", "v", "confidence"}));
    EXPECT_TRUE(robot["x"].is_number() && robot["y"].is_number() && robot["theta"].is_number());
  }
  const double worst = expectEveryRobotAtItsPixel(j["robots"]);
  // Field positions through the pose: the true ones to a few millimetres.
  for (const RobotState& t : scene_.robots) {
    for (const json& d : j["robots"]) {
      if (d["team"] == std::string(teamName(t.team)) && d["id"] == t.id) {
        EXPECT_LT(std::hypot(d["x"].get<double>() - t.x, d["y"].get<double>() - t.y), 0.005);
        EXPECT_LT(std::abs(wrapToPi(d["theta"].get<double>() - t.theta)), 1.5 * M_PI / 180);
      }
    }
  }
  ASSERT_EQ(j["balls"].size(), 1u);
  const json& ball = j["balls"][0];
  EXPECT_EQ(keys(ball), (std::set<std::string>{"x", "y", "u", "v", "area", "confidence"}));
  EXPECT_GT(ball["area"].get<double>(), 0);
  const double ball_px =
      (Eigen::Vector2d(ball["u"].get<double>(), ball["v"].get<double>()) - pixelOf(scene_.balls[0])).norm();
  EXPECT_LT(ball_px, 1.0);
  EXPECT_LT(
      std::hypot(ball["x"].get<double>() - scene_.balls[0].x, ball["y"].get<double>() - scene_.balls[0].y),
      0.005);
  std::printf("[ detect, pose ] worst robot %.3f px, ball %.3f px from their projections\n", worst, ball_px);
  // Every cause has a count; this clean frame rejects nothing of the scene.
  EXPECT_EQ(j["rejections"].size(), static_cast<std::size_t>(kNumRejectionCauses));
  EXPECT_EQ(j["rejections"]["area"], 0);
  // Each rejected candidate is one of the counted rejections, with its cause.
  long counted = 0;
  for (const auto& [cause, n] : j["rejections"].items()) counted += n.get<long>();
  EXPECT_LE(j["rejected_robots"].size(), static_cast<std::size_t>(counted));
  for (const json& c : j["rejected_robots"]) EXPECT_GT(j["rejections"][c["cause"].get<std::string>()], 0);
  const cv::Mat o = cv::imread(overlay, cv::IMREAD_COLOR);
  ASSERT_EQ(o.size(), cv::Size(camera().width(), camera().height()));
  // The field lines drawn in magenta through the pose: the centre circle's pixels.
  const Eigen::Vector2d on_circle = *camera().project({-0.5, 0, 0});
  const cv::Vec3b px = o.at<cv::Vec3b>(cvRound(on_circle.y()), cvRound(on_circle.x()));
  EXPECT_EQ(px, cv::Vec3b(255, 0, 255));
}

TEST_F(Detect, WithoutAPosePositionsAreNullAndPixelsStay) {
  const std::string out = kDir + "/no_pose.json";
  const ToolRun r = run("--image " + image() + " --colors " + table() + " --json " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = readJson(out);
  for (const json& robot : j["robots"]) {
    EXPECT_TRUE(robot["x"].is_null());
    EXPECT_TRUE(robot["y"].is_null());
    EXPECT_TRUE(robot["theta"].is_null());
  }
  const double worst = expectEveryRobotAtItsPixel(j["robots"]);
  ASSERT_EQ(j["balls"].size(), 1u);
  EXPECT_TRUE(j["balls"][0]["x"].is_null());
  EXPECT_TRUE(j["balls"][0]["y"].is_null());
  std::printf("[ detect, no pose ] worst robot %.3f px from its projection\n", worst);
}

TEST_F(Detect, BadArgumentsAndFilesExit2) {
  const std::string not_image = kDir + "/not_an_image.png";
  std::ofstream(not_image) << "garbage";
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"--colors " + table(), "--image"},
      {"--image " + image(), "--colors"},
      {"--image " + kDir + "/missing.png --colors " + table(), "missing.png"},
      {"--image " + not_image + " --colors " + table(), "not_an_image.png"},
      {"--image " + image() + " --colors " + image(), "frame.png"},
      {"--image " + image() + " --colors " + table() + " --camera-pose " + cameraPose(), "--camera-info"},
      {"--image " + image() + " --colors " + table() + " --field div_c", "div_c"},
      {"--image " + image() + " --colors " + table() + " --patterns nope", "nope"},
      {"--image " + image() + " --colors " + table() + " --json " + kDir + "/no/dir/out.json", "no/dir"},
      {"--image " + image() + " --colors " + table() + " --frobnicate", "frobnicate"},
  };
  for (const Case& c : cases) {
    const ToolRun r = run(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << "should name '" << c.expect << "': " << r.output;
  }
  EXPECT_EQ(run("--help").status, 0);
}

}  // namespace
