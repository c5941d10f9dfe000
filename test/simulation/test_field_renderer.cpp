// The synthetic camera must be right to sub-pixel level: everything downstream (blob
// centroids, pose accuracy, evaluation) is measured against it.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "support/scene_objects.h"

using namespace soccer_vision;
using soccer_vision::test::robotState;

namespace {

const FieldGeometry kField;

// Noise-free, evenly lit, single exposure: what the geometry checks need.
ScenarioConfig cleanScenario(const std::string& pattern = "two_tag") {
  ScenarioConfig s;
  s.pattern = pattern;
  s.lighting = LightingConfig{};
  s.sensor.noise_sigma = 0;
  return s;
}

CameraModel withoutDistortion(const CameraModel& c) {
  CameraIntrinsics k = c.intrinsics();
  k.dist = {};
  return CameraModel(k, c.fieldTCamera());
}

// A zero-distortion camera 8 m up that sees the whole carpet, ~12 mm per pixel.
CameraModel wholeFieldCamera() {
  CameraIntrinsics k;
  k.width = 640;
  k.height = 880;
  k.fx = k.fy = 660;
  k.cx = 319.5;
  k.cy = 439.5;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = Eigen::Vector3d::UnitY();
  pose.linear().col(1) = Eigen::Vector3d::UnitX();
  pose.linear().col(2) = -Eigen::Vector3d::UnitZ();
  pose.translation() = Eigen::Vector3d(0, 0, 8);
  return CameraModel(k, pose);
}

Eigen::Vector3d onTop(const RobotState& r, double local_x, double local_y, double z = 0.15) {
  const double c = std::cos(r.theta), s = std::sin(r.theta);
  return {r.x + c * local_x - s * local_y, r.y + s * local_x + c * local_y, z};
}

cv::Vec3f toVec(const cv::Vec3b& p) { return cv::Vec3f(p[0], p[1], p[2]); }

// Coverage-weighted moments of one paint over a known base colour: each pixel's colour
// is unmixed along the base->paint axis (exact for anti-aliased edges at unit gain).
struct PaintMoments {
  double area = 0, u = 0, v = 0;  // area in pixels; centroid after finish()
  void add(const cv::Vec3b& pixel, const cv::Vec3f& base, const cv::Vec3f& paint, int px, int py) {
    const cv::Vec3f axis = paint - base;
    const double a =
        std::clamp(static_cast<double>((toVec(pixel) - base).dot(axis) / axis.dot(axis)), 0.0, 1.0);
    area += a;
    u += a * px;
    v += a * py;
  }
  Eigen::Vector2d centroid() const { return {u / area, v / area}; }
};

// Moments of one marker of `robot`, over the pixels whose ray meets the top plane within
// `margin` of the shape (the gap to the next marker is >= 20 mm).
PaintMoments measureMarker(const cv::Mat& image, const CameraModel& camera, const RobotState& robot,
                           const MarkerShape& shape, ColorClass color, double margin = 0.004) {
  const auto centre = camera.project(onTop(robot, shape.x, shape.y));
  PaintMoments m;
  const int reach = 20;
  for (int v = static_cast<int>(centre->y()) - reach; v <= static_cast<int>(centre->y()) + reach; ++v)
    for (int u = static_cast<int>(centre->x()) - reach; u <= static_cast<int>(centre->x()) + reach; ++u) {
      const Eigen::Vector3d p = *camera.pixelToField(Eigen::Vector2d(u, v), 0.15);
      const double c = std::cos(robot.theta), s = std::sin(robot.theta);
      const double lx = c * (p.x() - robot.x) + s * (p.y() - robot.y) - shape.x;
      const double ly = -s * (p.x() - robot.x) + c * (p.y() - robot.y) - shape.y;
      const double sdf = shape.kind == MarkerShape::Kind::Disc
                             ? std::hypot(lx, ly) - shape.radius
                             : std::max(std::abs(lx) - shape.size_x / 2, std::abs(ly) - shape.size_y / 2);
      if (sdf < margin)
        m.add(image.at<cv::Vec3b>(v, u), classAlbedo(ColorClass::RobotTop), classAlbedo(color), u, v);
    }
  return m;
}

// Moments of the ball over the pixels whose ray passes within radius + 4 mm of its centre.
PaintMoments measureBall(const cv::Mat& image, const CameraModel& camera, const BallState& ball) {
  const Eigen::Vector3d b(ball.x, ball.y, ball.z);
  const auto centre = camera.project(b);
  PaintMoments m;
  for (int v = static_cast<int>(centre->y()) - 10; v <= static_cast<int>(centre->y()) + 10; ++v)
    for (int u = static_cast<int>(centre->x()) - 10; u <= static_cast<int>(centre->x()) + 10; ++u) {
      const Eigen::Vector3d ray = camera.pixelRay(Eigen::Vector2d(u, v));
      const Eigen::Vector3d w = b - camera.cameraCentre();
      if ((w - w.dot(ray) * ray).norm() < 0.0215 + 0.004)
        m.add(image.at<cv::Vec3b>(v, u), classAlbedo(ColorClass::Carpet), classAlbedo(ColorClass::Orange), u,
              v);
    }
  return m;
}

// Pixels per square metre on the plane z at field point p (undistorted camera).
double pixelsPerSquareMetre(const CameraModel& camera, const Eigen::Vector3d& p) {
  const double e = 0.01;
  const Eigen::Vector2d o = *camera.projectUndistorted(p);
  const Eigen::Vector2d dx = (*camera.projectUndistorted(p + Eigen::Vector3d(e, 0, 0)) - o) / e;
  const Eigen::Vector2d dy = (*camera.projectUndistorted(p + Eigen::Vector3d(0, e, 0)) - o) / e;
  return std::abs(dx.x() * dy.y() - dx.y() * dy.x());
}

cv::Mat renderImage(const FieldRenderer& renderer, const SceneState& scene, std::int64_t frame = 0) {
  RenderedFrame f;
  renderer.render(scene, frame, f);
  return f.image;
}

}  // namespace

TEST(FieldRenderer, MarkersAndBallAppearWhereTheCameraProjectsThem) {
  const ScenarioConfig scenario = cleanScenario();
  const PatternSet patterns = PatternSet::twoTag();
  SceneState scene;
  scene.robots = {robotState(Team::Blue, 0, -2.4, -1.1, 0.7), robotState(Team::Yellow, 3, -0.8, 2.2, -2.5),
                  robotState(Team::Blue, 4, -3.9, -2.5, 2.0)};
  scene.balls.resize(1);
  scene.balls[0].x = -1.7;
  scene.balls[0].y = 1.3;

  const CameraModel distorted = CameraModel::defaultCamera(kField, 0);
  struct Case {
    CameraModel camera;
    double tolerance_px;
  };
  for (const Case& c : {Case{withoutDistortion(distorted), 0.1}, Case{distorted, 0.15}}) {
    const FieldRenderer renderer(c.camera, kField, patterns, scenario);
    const cv::Mat image = renderImage(renderer, scene);
    for (const RobotState& robot : scene.robots) {
      ASSERT_TRUE(renderer.robotVisible(robot));
      for (const ColoredMarker& marker : patterns.markers(robot.team, robot.id)) {
        const PaintMoments m = measureMarker(image, c.camera, robot, marker.shape, marker.color);
        const Eigen::Vector2d expected = *c.camera.project(onTop(robot, marker.shape.x, marker.shape.y));
        EXPECT_LT((m.centroid() - expected).norm(), c.tolerance_px)
            << colorClassName(marker.color) << " of robot at " << robot.x << ", " << robot.y << ": centroid "
            << m.centroid().transpose() << " expected " << expected.transpose();
      }
    }
    const BallState& ball = scene.balls[0];
    ASSERT_TRUE(renderer.ballVisible(ball, scene.robots));
    const PaintMoments m = measureBall(image, c.camera, ball);
    const Eigen::Vector2d expected = *c.camera.project({ball.x, ball.y, ball.z});
    EXPECT_LT((m.centroid() - expected).norm(), c.tolerance_px)
        << "ball centroid " << m.centroid().transpose() << " expected " << expected.transpose();
  }
}

TEST(FieldRenderer, TwoTagMarkersHaveTheDesignDimensions) {
  const CameraModel camera = withoutDistortion(CameraModel::defaultCamera(kField, 0));
  const PatternSet patterns = PatternSet::twoTag();
  const FieldRenderer renderer(camera, kField, patterns, cleanScenario());
  SceneState scene;
  scene.robots = {robotState(Team::Yellow, 1, -2.0, 0.8, 0.3)};
  const cv::Mat image = renderImage(renderer, scene);
  const RobotState& robot = scene.robots[0];

  // The two-tag pattern: team rectangle 80 x 30 mm, 20 mm behind the centre; role disc 40 mm, 45 mm ahead.
  const auto markers = patterns.markers(robot.team, robot.id);
  ASSERT_EQ(markers.size(), 2u);
  const double team_area = measureMarker(image, camera, robot, markers[0].shape, ColorClass::Yellow).area;
  const double role_area = measureMarker(image, camera, robot, markers[1].shape, ColorClass::Purple).area;
  const double team_expected = 0.080 * 0.030 * pixelsPerSquareMetre(camera, onTop(robot, -0.020, 0));
  const double role_expected = M_PI * 0.020 * 0.020 * pixelsPerSquareMetre(camera, onTop(robot, 0.045, 0));
  EXPECT_NEAR(team_area / team_expected, 1.0, 0.02) << team_area << " px vs " << team_expected;
  EXPECT_NEAR(role_area / role_expected, 1.0, 0.02) << role_area << " px vs " << role_expected;
}

TEST(FieldRenderer, SslDotsSitAtTheDesignLayout) {
  const CameraModel camera = withoutDistortion(CameraModel::defaultCamera(kField, 0));
  const PatternSet patterns = PatternSet::ssl();
  const FieldRenderer renderer(camera, kField, patterns, cleanScenario("ssl"));
  SceneState scene;
  scene.robots = {robotState(Team::Blue, 5, -2.7, -0.9, 1.2)};  // id 5 = 0101: green pink green pink
  const cv::Mat image = renderImage(renderer, scene);
  const RobotState& robot = scene.robots[0];
  const auto markers = patterns.markers(robot.team, robot.id);
  ASSERT_EQ(markers.size(), 5u);

  MarkerShape centre_disc;
  centre_disc.radius = 0.025;
  const double team_area = measureMarker(image, camera, robot, centre_disc, ColorClass::Blue).area;
  EXPECT_NEAR(team_area / (M_PI * 0.025 * 0.025 * pixelsPerSquareMetre(camera, onTop(robot, 0, 0))), 1.0,
              0.02);

  // The SSL pattern: 40 mm discs 65 mm from the centre at -60, +60, +135, -135 degrees.
  const double angles_deg[] = {-60, 60, 135, -135};
  const ColorClass colors[] = {ColorClass::Green, ColorClass::Pink, ColorClass::Green, ColorClass::Pink};
  for (int k = 0; k < 4; ++k) {
    MarkerShape dot;
    dot.radius = 0.020;
    dot.x = 0.065 * std::cos(angles_deg[k] * M_PI / 180);
    dot.y = 0.065 * std::sin(angles_deg[k] * M_PI / 180);
    const PaintMoments m = measureMarker(image, camera, robot, dot, colors[k]);
    EXPECT_NEAR(m.area / (M_PI * 0.020 * 0.020 * pixelsPerSquareMetre(camera, onTop(robot, dot.x, dot.y))),
                1.0, 0.02)
        << "dot at " << angles_deg[k] << " deg";
    // Back to the robot frame: the measured centroid's distance and bearing.
    const Eigen::Vector3d p = *camera.pixelToField(m.centroid(), 0.15);
    const double c = std::cos(robot.theta), s = std::sin(robot.theta);
    const double lx = c * (p.x() - robot.x) + s * (p.y() - robot.y);
    const double ly = -s * (p.x() - robot.x) + c * (p.y() - robot.y);
    EXPECT_NEAR(std::hypot(lx, ly), 0.065, 0.0005) << "dot at " << angles_deg[k] << " deg";
    EXPECT_NEAR(std::atan2(ly, lx) * 180 / M_PI, angles_deg[k], 0.5);
  }
}

TEST(FieldRenderer, LabelsNameTheDominantSurface) {
  const CameraModel camera = CameraModel::defaultCamera(kField, 0);
  const PatternSet patterns = PatternSet::twoTag();
  const FieldRenderer renderer(camera, kField, patterns, cleanScenario());
  SceneState scene;
  scene.robots = {robotState(Team::Blue, 2, -2.0, -1.5, -0.4), robotState(Team::Yellow, 4, -0.6, 2.4, 2.0)};
  scene.balls.resize(1);
  scene.balls[0].x = -3.0;
  scene.balls[0].y = 0.5;
  const cv::Mat labels = renderer.renderLabels(scene);
  ASSERT_EQ(labels.type(), CV_8UC1);
  ASSERT_EQ(labels.size(), cv::Size(camera.width(), camera.height()));
  auto labelAt = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d px = *camera.project(p);
    if (!camera.inImage(px, 1)) return ColorClass::Count;
    return static_cast<ColorClass>(labels.at<std::uint8_t>(static_cast<int>(std::lround(px.y())),
                                                           static_cast<int>(std::lround(px.x()))));
  };
  for (const RobotState& robot : scene.robots) {
    EXPECT_EQ(labelAt(onTop(robot, -0.020, 0)), teamColor(robot.team));
    EXPECT_EQ(labelAt(onTop(robot, 0.045, 0)), robot.id == 2 ? ColorClass::SkyBlue : ColorClass::Red);
    EXPECT_EQ(labelAt(onTop(robot, 0.0, 0.065)), ColorClass::RobotTop);
    // The side wall facing the camera, half way up, is neither top nor carpet.
    const Eigen::Vector2d to_camera =
        (camera.cameraCentre().head<2>() - Eigen::Vector2d(robot.x, robot.y)).normalized();
    EXPECT_EQ(labelAt({robot.x + 0.0899 * to_camera.x(), robot.y + 0.0899 * to_camera.y(), 0.05}),
              ColorClass::None);
  }
  EXPECT_EQ(labelAt({-3.0, 0.5, 0.0215}), ColorClass::Orange);
  EXPECT_EQ(labelAt({-1.0, 1.0, 0.0}), ColorClass::Carpet);
  EXPECT_EQ(labelAt({0.0, 1.5, 0.0}), ColorClass::Line);                   // halfway line
  EXPECT_EQ(labelAt({-kField.halfLength(), 0.3, 0.0}), ColorClass::Line);  // goal line
  EXPECT_EQ(labelAt({-4.7, 0.0, 0.0}), ColorClass::Carpet);                // boundary
  EXPECT_EQ(labelAt({-4.9, 0.0, 0.0}), ColorClass::None);                  // floor beyond the carpet
}

TEST(FieldRenderer, SameSeedAndFrameGiveTheSameImage) {
  const CameraModel camera = CameraModel::defaultCamera(kField, 1, 640, 512);
  ScenarioConfig scenario;  // default: noise on
  scenario.lighting.flicker = 0.05;
  scenario.lighting.uneven_ratio = 1.5;
  SceneState scene;
  scene.robots = {robotState(Team::Blue, 0, 2.0, 0.5, 1.0)};
  scene.balls.resize(1);
  scene.balls[0].x = 1.5;

  const cv::Mat a = renderImage(FieldRenderer(camera, kField, PatternSet::twoTag(), scenario), scene, 7);
  const cv::Mat b = renderImage(FieldRenderer(camera, kField, PatternSet::twoTag(), scenario), scene, 7);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);

  const FieldRenderer renderer(camera, kField, PatternSet::twoTag(), scenario);
  EXPECT_GT(cv::norm(a, renderImage(renderer, scene, 8), cv::NORM_L1), 0.0);
  scenario.seed += 1;
  const cv::Mat other_seed =
      renderImage(FieldRenderer(camera, kField, PatternSet::twoTag(), scenario), scene, 7);
  EXPECT_GT(cv::norm(a, other_seed, cv::NORM_L1), 0.0);
}

TEST(FieldRenderer, CarpetLightingSpansTheUnevenRatio) {
  ScenarioConfig scenario =
      loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/uneven_drift.yaml");
  ASSERT_GT(scenario.lighting.uneven_ratio, 1.2);
  scenario.sensor.noise_sigma = 0;
  const CameraModel camera = wholeFieldCamera();
  const FieldRenderer renderer(camera, kField, PatternSet::twoTag(), scenario);
  const SceneState empty;
  const cv::Mat image = renderImage(renderer, empty);
  cv::Mat carpet = renderer.renderLabels(empty) == static_cast<int>(ColorClass::Carpet);
  cv::erode(carpet, carpet, cv::Mat::ones(5, 5, CV_8U));  // away from lines and edges

  // Illumination = green / carpet green, averaged over 8 x 8 blocks that are all carpet.
  const float albedo = classAlbedo(ColorClass::Carpet)[1];
  double lo = HUGE_VAL, hi = 0;
  for (int by = 0; by + 8 <= image.rows; by += 8)
    for (int bx = 0; bx + 8 <= image.cols; bx += 8) {
      const cv::Rect block(bx, by, 8, 8);
      if (cv::countNonZero(carpet(block)) < 64) continue;
      cv::Mat green;
      cv::extractChannel(image(block), green, 1);
      const double illumination = cv::mean(green)[0] / albedo;
      lo = std::min(lo, illumination);
      hi = std::max(hi, illumination);
    }
  EXPECT_NEAR(hi / lo, scenario.lighting.uneven_ratio, 0.05 * scenario.lighting.uneven_ratio);
}

TEST(IlluminationModel, SpatialGainSpansTheRatioWithTheGivenMean) {
  for (double ratio : {1.0, 1.3, 1.8, 3.0}) {
    LightingConfig config;
    config.uneven_ratio = ratio;
    config.brightness = 0.9;
    const IlluminationModel model(config, kField, 42);
    double lo = HUGE_VAL, hi = 0, sum = 0;
    int n = 0;
    for (double x = -4.8; x <= 4.8001; x += 0.04)
      for (double y = -3.3; y <= 3.3001; y += 0.04, ++n) {
        const double g = model.spatialGain(x, y);
        lo = std::min(lo, g);
        hi = std::max(hi, g);
        sum += g;
      }
    EXPECT_NEAR(hi / lo, ratio, 1e-3 * ratio);
    EXPECT_NEAR(sum / n, 0.9, 0.01);
  }
}

TEST(IlluminationModel, GlobalGainDriftsAndFlickersDeterministically) {
  LightingConfig config;
  config.drift_amplitude = 0.1;
  config.drift_period = 10;
  const IlluminationModel drift(config, kField, 3);
  double lo = HUGE_VAL, hi = 0;
  for (double t = 0; t < 10; t += 0.05) {
    lo = std::min(lo, drift.globalGain(t, 0));
    hi = std::max(hi, drift.globalGain(t, 0));
  }
  EXPECT_NEAR(lo, 0.9, 1e-3);
  EXPECT_NEAR(hi, 1.1, 1e-3);

  config.drift_amplitude = 0;
  config.flicker = 0.05;
  const IlluminationModel flicker(config, kField, 3);
  double sum = 0, sum2 = 0;
  const int n = 2000;
  for (int frame = 0; frame < n; ++frame) {
    const double g = flicker.globalGain(1.0, frame);
    EXPECT_EQ(g, flicker.globalGain(5.0, frame));
    sum += g;
    sum2 += g * g;
  }
  EXPECT_NEAR(sum / n, 1.0, 0.005);
  EXPECT_NEAR(std::sqrt(sum2 / n - (sum / n) * (sum / n)), 0.05, 0.005);
  EXPECT_NE(flicker.globalGain(0, 1), flicker.globalGain(0, 2));
}

TEST(FieldRenderer, BayerMosaicSamplesTheColourImage) {
  const CameraModel camera = CameraModel::defaultCamera(kField, 0, 320, 256);
  SceneState scene;
  scene.robots = {robotState(Team::Blue, 1, -2.0, 0.4, 0.2)};
  ScenarioConfig scenario = cleanScenario();
  scenario.sensor.noise_sigma = 2;  // noise is part of the colour image the mosaic samples
  const cv::Mat bgr = renderImage(FieldRenderer(camera, kField, PatternSet::twoTag(), scenario), scene, 3);

  // Channel (B = 0, G = 1, R = 2) at (row & 1, col & 1) for each pattern.
  const std::pair<std::string, std::array<int, 4>> patterns[] = {
      {"rggb", {2, 1, 1, 0}}, {"bggr", {0, 1, 1, 2}}, {"gbrg", {1, 0, 2, 1}}, {"grbg", {1, 2, 0, 1}}};
  for (const auto& [name, channels] : patterns) {
    scenario.sensor.bayer = name;
    const FieldRenderer renderer(camera, kField, PatternSet::twoTag(), scenario);
    EXPECT_EQ(renderer.encoding(), "bayer_" + name + "8");
    RenderedFrame frame;
    renderer.render(scene, 3, frame);
    EXPECT_EQ(frame.encoding, "bayer_" + name + "8");
    ASSERT_EQ(frame.image.type(), CV_8UC1);
    int mismatches = 0;
    for (int v = 0; v < bgr.rows; ++v)
      for (int u = 0; u < bgr.cols; ++u)
        mismatches +=
            frame.image.at<std::uint8_t>(v, u) != bgr.at<cv::Vec3b>(v, u)[channels[(v & 1) * 2 + (u & 1)]];
    EXPECT_EQ(mismatches, 0) << name;
  }
}

TEST(FieldRenderer, DrawsIntoAPreallocatedImage) {
  const CameraModel camera = CameraModel::defaultCamera(kField, 0, 320, 256);
  SceneState scene;
  scene.robots = {robotState(Team::Blue, 1, -2.0, 0.4, 0.2)};
  for (const char* bayer : {"", "grbg"}) {
    ScenarioConfig scenario;
    scenario.sensor.bayer = bayer;
    scenario.sensor.jpeg_quality = 90;
    const FieldRenderer renderer(camera, kField, PatternSet::twoTag(), scenario);
    std::vector<std::uint8_t> buffer(320 * 256 * (*bayer ? 1 : 3));  // e.g. a message's data
    RenderedFrame frame;
    frame.image = cv::Mat(256, 320, *bayer ? CV_8UC1 : CV_8UC3, buffer.data());
    renderer.render(scene, 0, frame);
    EXPECT_EQ(frame.image.data, buffer.data());
    EXPECT_GT(cv::norm(frame.image, cv::NORM_L1), 0.0);
  }
}

TEST(FieldRenderer, JpegAndBlurChangeThePictureButKeepItsContent) {
  const CameraModel camera = CameraModel::defaultCamera(kField, 0, 640, 512);
  RobotState robot = robotState(Team::Blue, 0, -2.0, 0.4, 0.2);
  robot.vx = 4.0;
  SceneState scene;
  scene.robots = {robot};
  ScenarioConfig scenario = cleanScenario();
  const cv::Mat sharp = renderImage(FieldRenderer(camera, kField, PatternSet::twoTag(), scenario), scene);

  scenario.sensor.jpeg_quality = 75;
  const cv::Mat jpeg = renderImage(FieldRenderer(camera, kField, PatternSet::twoTag(), scenario), scene);
  EXPECT_GT(cv::norm(sharp, jpeg, cv::NORM_INF), 0.0);
  EXPECT_LT(cv::norm(sharp, jpeg, cv::NORM_L1) / (3.0 * sharp.total()), 3.0);  // artefacts, not damage

  // A 4 ms exposure at 4 m/s smears the robot over 16 mm, centred 8 mm ahead.
  scenario.sensor.jpeg_quality = 0;
  scenario.sensor.blur_samples = 8;
  scenario.sensor.exposure = 0.004;
  const cv::Mat blurred = renderImage(FieldRenderer(camera, kField, PatternSet::twoTag(), scenario), scene);
  EXPECT_GT(cv::norm(sharp, blurred, cv::NORM_INF), 10.0);
  const MarkerShape role = PatternSet::twoTag().markers(Team::Blue, 0)[1].shape;
  RobotState mid_exposure = robot;
  mid_exposure.x += 0.008;
  const Eigen::Vector2d centroid =
      measureMarker(blurred, camera, mid_exposure, role, ColorClass::Pink, 0.012).centroid();
  EXPECT_LT((centroid - *camera.project(onTop(mid_exposure, role.x, role.y))).norm(), 0.05);
}

// The truth's ball visibility is what the image shows: a ball beside a robot on the robot's
// far side from the camera's nadir lies behind its body and is not visible (the labels show
// less than half of it); beside it on the near side, or alone, it is.
TEST(FieldRenderer, ABallBehindARobotIsNotVisible) {
  const CameraModel camera = CameraModel::defaultCamera(kField, 0);
  const PatternSet patterns = PatternSet::twoTag();
  const FieldRenderer renderer(camera, kField, patterns, cleanScenario());
  const Eigen::Vector2d nadir = camera.cameraCentre().head<2>();
  const Eigen::Vector2d robot_at = nadir + Eigen::Vector2d(-1.0, -1.7);  // 2 m from the nadir
  const Eigen::Vector2d outwards = (robot_at - nadir).normalized();
  const double touching = patterns.robot_radius + 0.0215 + 0.002;
  struct Case {
    Eigen::Vector2d ball;
    bool visible;
  };
  for (const Case& c : {Case{robot_at + outwards * touching, false},
                        Case{robot_at - outwards * touching, true}, Case{robot_at + outwards * 0.5, true}}) {
    SceneState scene;
    scene.robots = {robotState(Team::Blue, 2, robot_at.x(), robot_at.y(), 0.4)};
    scene.balls.resize(1);
    scene.balls[0].x = c.ball.x();
    scene.balls[0].y = c.ball.y();
    const cv::Mat labels = renderer.renderLabels(scene);
    SceneState alone = scene;
    alone.robots.clear();
    const cv::Mat unoccluded = renderer.renderLabels(alone);
    const double shown = cv::countNonZero(labels == static_cast<int>(ColorClass::Orange));
    const double whole = cv::countNonZero(unoccluded == static_cast<int>(ColorClass::Orange));
    ASSERT_GT(whole, 20);
    EXPECT_EQ(renderer.ballVisible(scene.balls[0], scene.robots), c.visible)
        << "ball at " << c.ball.transpose() << ": " << shown << " of " << whole << " px shown";
    EXPECT_EQ(shown >= whole / 2, c.visible) << shown << " of " << whole << " px shown";
    EXPECT_TRUE(renderer.ballVisible(scene.balls[0], {}));
  }
}

// A robot 2 m from the nadir, and a ball `distance` from its centre on the line away from the
// nadir (negative: towards it), as a person calibrating may find them.
struct BallBesideARobot {
  const CameraModel camera = CameraModel::defaultCamera(kField, 0);
  const PatternSet patterns = PatternSet::twoTag();
  const FieldRenderer renderer{camera, kField, patterns, cleanScenario()};
  const Eigen::Vector2d nadir = camera.cameraCentre().head<2>();
  const Eigen::Vector2d robot_at = nadir + Eigen::Vector2d(-1.0, -1.7);
  const Eigen::Vector2d outwards = (robot_at - nadir).normalized();

  SceneState scene(double distance) const {
    SceneState s;
    s.robots = {robotState(Team::Blue, 2, robot_at.x(), robot_at.y(), 0.4)};
    s.balls.resize(1);
    s.balls[0].x = robot_at.x() + distance * outwards.x();
    s.balls[0].y = robot_at.y() + distance * outwards.y();
    return s;
  }
  // The samples a user draws on `scene`: the balls nothing hides, or (as the user was once
  // given them) every ball.
  ColorSamples painted(const SceneState& scene, bool wholly_visible_only) const {
    const SampleOptions user = SampleOptions::drawnByUser(2);
    return wholly_visible_only ? renderer.paintedSamples(scene, user)
                               : calibrationSamples(scene, camera, kField, patterns, user);
  }
  // Of the pixels in every ball's polygon, how many show the ball; `total`: all of them.
  int ballPixels(const SceneState& scene, int& total) const {
    const cv::Mat labels = renderer.renderLabels(scene);
    const auto pixels = samplePixelPositions(labels.size(), painted(scene, false));
    int ball = 0;
    total = 0;
    for (const cv::Point& p : pixels.at(ColorClass::Orange)) {
      ++total;
      ball += labels.at<std::uint8_t>(p) == static_cast<int>(ColorClass::Orange);
    }
    return ball;
  }
};

// A person calibrating paints the balls the image shows, and no ball hidden behind a robot:
// held-out seed 9086's rand_bayer_ssl had its ball's polygon drawn on a robot's black top
// (the ball behind it), so the table's orange was black, the ball was never found and
// robots' rims at the image's edge were taken for it (41 false balls).
TEST(FieldRenderer, APersonCalibratingPaintsNoBallHiddenBehindARobot) {
  const BallBesideARobot b;
  const double touching = b.patterns.robot_radius + 0.0215 + 0.002;
  for (const double side : {1.0, -1.0}) {  // behind the robot, in front of it
    const SceneState scene = b.scene(side * touching);
    const bool visible = side < 0;
    EXPECT_EQ(b.painted(scene, true).count(ColorClass::Orange) == 1, visible);
    EXPECT_EQ(b.renderer.withWhollyVisibleBalls(scene).robots.size(), 1u);
    // Every ball's polygon, as the user was once given it: the hidden one lies on the top.
    ASSERT_EQ(b.painted(scene, false).count(ColorClass::Orange), 1u);
    int total = 0;
    const int orange = b.ballPixels(scene, total);
    ASSERT_GT(total, 0);
    EXPECT_EQ(2 * orange > total, visible) << orange << " of " << total << " polygon pixels show the ball";
  }
}

// Nor one partly hidden: the truth counts a ball as visible when half of it shows, but a
// polygon 2 px inside its outline would then take in the robot hiding the rest.
TEST(FieldRenderer, APersonCalibratingPaintsNoBallPartlyHiddenBehindARobot) {
  const BallBesideARobot b;
  // Behind the robot, moved away from it until part of the ball shows.
  SceneState scene;
  double shown = 0, d = b.patterns.robot_radius + 0.0235;
  for (; d < 0.5 && !(shown >= 0.5 && shown < 1); d += 0.002) {
    scene = b.scene(d);
    shown = b.renderer.ballShown(scene.balls[0], scene.robots);
  }
  ASSERT_GE(shown, 0.5);
  ASSERT_LT(shown, 1.0);
  EXPECT_TRUE(b.renderer.ballVisible(scene.balls[0], scene.robots)) << "the truth counts it";
  EXPECT_EQ(b.painted(scene, true).count(ColorClass::Orange), 0u);
  // Its whole polygon holds pixels of the robot.
  ASSERT_EQ(b.painted(scene, false).count(ColorClass::Orange), 1u);
  int total = 0;
  const int ball = b.ballPixels(scene, total);
  EXPECT_GT(total - ball, 0) << "shown " << shown;
  // Moved on until nothing hides it, it is painted.
  scene = b.scene(d + 0.1);
  ASSERT_EQ(b.renderer.ballShown(scene.balls[0], scene.robots), 1.0);
  EXPECT_EQ(b.painted(scene, true).count(ColorClass::Orange), 1u);
}
