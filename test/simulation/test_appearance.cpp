// Appearance randomisation (scenario `appearance` and `lens`): reproducible for a seed,
// different for another, and each effect measurably there, at the size its parameter says.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/simulation/ball_light.h"
#include "soccer_vision/simulation/distractors.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/lamps.h"
#include "soccer_vision/simulation/scenario_camera.h"

using namespace soccer_vision;

namespace {

const FieldGeometry kField;
const PatternSet kPatterns = PatternSet::twoTag();

// Even light, no noise, nothing randomised: the reference each effect is compared with.
ScenarioConfig plain() {
  ScenarioConfig s;
  s.width = 640;
  s.height = 512;
  s.sensor.noise_sigma = 0;
  return s;
}

CameraModel cameraOf(const ScenarioConfig& s) { return scenarioCamera(kField, 0, s); }

cv::Mat render(const ScenarioConfig& s, const SceneState& scene, std::int64_t frame = 0) {
  const FieldRenderer renderer(cameraOf(s), kField, kPatterns, s);
  RenderedFrame out;
  renderer.render(scene, frame, out);
  return out.image;
}

SceneState oneRobot(double x = -2.0, double y = 0.5) {
  SceneState scene;
  RobotState r;
  r.team = Team::Blue;
  r.id = 2;
  r.x = x;
  r.y = y;
  scene.robots.push_back(r);
  return scene;
}

// Every effect at once, as the rand_* presets use them.
ScenarioConfig everything(std::uint64_t seed) {
  ScenarioConfig s = plain();
  s.seed = seed;
  s.sensor.noise_sigma = 2;
  AppearanceConfig& a = s.appearance;
  a.marker_albedo_spread = 0.08;
  a.carpet_fibre = 0.05;
  a.carpet_patches = 0.1;
  a.mowing_stripes = 0.05;
  a.lamps = 6;
  a.lamp_drift = 0.3;
  a.shadow = 0.4;
  a.color_temperature = 4000;
  a.white_balance_error = 0.08;
  a.gamma = 0.8;
  a.saturation = 0.9;
  a.vignetting = 0.3;
  a.lens_blur = 0.7;
  a.shot_noise = 1.0;
  a.distractors = 12;
  s.lens.k1 = -0.3;
  s.lens.k2 = 0.08;
  s.lens.tilt_deg = 5;
  return s;
}

double meanAbsDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3;
}

// Mean BGR over a small square around a pixel.
cv::Scalar meanAround(const cv::Mat& image, const Eigen::Vector2d& px, int half = 3) {
  const cv::Rect r(static_cast<int>(px.x()) - half, static_cast<int>(px.y()) - half, 2 * half + 1,
                   2 * half + 1);
  return cv::mean(image(r & cv::Rect(0, 0, image.cols, image.rows)));
}

}  // namespace

TEST(Appearance, SameSeedGivesTheSameImageAnotherSeedAnotherLook) {
  const SceneState scene = oneRobot();
  const cv::Mat a = render(everything(5), scene, 3), b = render(everything(5), scene, 3);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  // Another seed: other lamps, carpet, prints, white balance, tilt direction, distractors.
  const cv::Mat c = render(everything(6), scene, 3);
  EXPECT_GT(meanAbsDifference(a, c), 5.0);
}

TEST(Appearance, VignettingDarkensTheCornersByItsShare) {
  ScenarioConfig s = plain();
  const cv::Mat flat = render(s, {});
  s.appearance.vignetting = 0.4;
  const cv::Mat vignetted = render(s, {});
  const auto ratio = [&](int u, int v) {
    const cv::Scalar a = meanAround(vignetted, Eigen::Vector2d(u, v), 2),
                     b = meanAround(flat, Eigen::Vector2d(u, v), 2);
    return (a[0] + a[1] + a[2]) / (b[0] + b[1] + b[2]);
  };
  EXPECT_NEAR(ratio(320, 256), 1.0, 0.02);
  for (const auto& [u, v] : {std::pair{2, 2}, std::pair{637, 2}, std::pair{2, 509}, std::pair{637, 509}})
    EXPECT_NEAR(ratio(u, v), 0.6, 0.03) << u << ", " << v;
}

TEST(Appearance, DistractorsLieOutsideTheFieldLines) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const std::vector<Distractor> layout = distractorLayout(40, kField, seed);
    ASSERT_GE(layout.size(), 40u);  // people are four parts
    for (const Distractor& d : layout)
      EXPECT_GE(distanceOutsideLines(kField, d.x, d.y), d.boundingRadius() + 0.02);
  }
  // Rendered: they change pixels, and only pixels whose floor lies outside the lines.
  ScenarioConfig s = plain();
  const cv::Mat without = render(s, {});
  s.appearance.distractors = 40;
  const cv::Mat with = render(s, {});
  const CameraModel camera = cameraOf(s);
  const Eigen::Vector3d centre = camera.cameraCentre();
  int changed = 0;
  for (int v = 0; v < with.rows; ++v)
    for (int u = 0; u < with.cols; ++u) {
      if (with.at<cv::Vec3b>(v, u) == without.at<cv::Vec3b>(v, u)) continue;
      ++changed;
      const Eigen::Vector3d ray = camera.pixelRay(Eigen::Vector2d(u, v));
      const Eigen::Vector3d floor = centre - centre.z() / ray.z() * ray;
      // A pixel's footprint (~5 mm) may reach over a shape's anti-aliased edge.
      EXPECT_GT(distanceOutsideLines(kField, floor.x(), floor.y()), 0.0) << u << ", " << v;
    }
  EXPECT_GT(changed, 500);
}

TEST(Appearance, LampsFallOffWithInverseSquareAndCosine) {
  AppearanceConfig a;
  a.lamps = 3;
  a.lamp_height = 6;
  const LampSet lamps(a, kField, 7);
  ASSERT_EQ(lamps.size(), 3u);
  const Lamp& l = lamps.lamp(0);
  // E ~ H / d^3: 3 m aside from beneath the lamp, (1 + 9 / H^2)^1.5 less.
  const double expected = std::pow(1 + 9.0 / (l.z * l.z), 1.5);
  EXPECT_NEAR(lamps.irradiance(0, l.x, l.y) / lamps.irradiance(0, l.x + 3, l.y), expected, 1e-9);
}

TEST(Appearance, RobotsCastSoftShadowsAwayFromTheLamp) {
  ScenarioConfig s = plain();
  s.appearance.lamps = 1;
  s.appearance.shadow = 0.5;
  // Below the camera: its body hides no carpet around it.
  const CameraModel camera = cameraOf(s);
  const SceneState scene = oneRobot(camera.cameraCentre().x(), camera.cameraCentre().y());
  const cv::Mat image = render(s, scene);
  const LampSet lamps(s.appearance, kField, s.seed);
  const RobotState& r = scene.robots.front();
  const Eigen::Vector2d base(r.x, r.y);
  const Eigen::Vector2d tip = lamps.shadowTip(0, r.x, r.y, kPatterns.height(r.team));
  const double length = (tip - base).norm();
  ASSERT_GT(length, 0.03);  // the lamp is not overhead: the shadow reaches beyond the body
  const Eigen::Vector2d away = (tip - base) / length;
  // Beyond the body by half the shadow's length: in the shadow away from the lamp, lit towards it.
  const double d = kPatterns.robot_radius + length / 2;
  const Eigen::Vector2d behind = base + d * away, before = base - d * away;
  const cv::Scalar dark = meanAround(image, *camera.project(Eigen::Vector3d(behind.x(), behind.y(), 0)), 1);
  const cv::Scalar lit = meanAround(image, *camera.project(Eigen::Vector3d(before.x(), before.y(), 0)), 1);
  // One lamp brings all the light: the shadow keeps 1 - 0.5 of it.
  EXPECT_NEAR(dark[1] / lit[1], 0.5, 0.08);
}

TEST(Appearance, EveryPrintedMarkerHasItsOwnColourInEveryFrame) {
  ScenarioConfig s = plain();
  // Full size: the 3 x 3 px window lies wholly inside the 40 mm disc (8 px across).
  s.width = 1280;
  s.height = 1024;
  const CameraModel camera = cameraOf(s);
  const auto idMarker = [&](const ScenarioConfig& config, double x) {
    const SceneState scene = oneRobot(x, 0.5);
    // The two-tag id disc lies 45 mm ahead of the centre (heading +x).
    return meanAround(render(config, scene), *camera.project(Eigen::Vector3d(x + 0.045, 0.5, 0.15)), 2);
  };
  const cv::Scalar nominal = idMarker(s, -2.0);
  s.appearance.marker_albedo_spread = 0.15;
  const cv::Scalar printed = idMarker(s, -2.0), printed_elsewhere = idMarker(s, -2.5);
  double change = 0, same = 0;
  for (int c = 0; c < 3; ++c) {
    change = std::max(change, std::abs(printed[c] / nominal[c] - 1));
    same = std::max(same, std::abs(printed[c] / printed_elsewhere[c] - 1));
  }
  EXPECT_GT(change, 0.05);  // 0.15 relative std-dev over three channels
  EXPECT_LT(same, 0.03);    // the same print wherever the robot goes
}

TEST(Appearance, CarpetTextureAndShotNoiseAreThere) {
  ScenarioConfig s = plain();
  const auto carpetSpread = [&](const ScenarioConfig& config) {
    // A patch of carpet away from the lines (the penalty area's inside).
    const cv::Mat image = render(config, {});
    const CameraModel camera = cameraOf(config);
    const Eigen::Vector2d px = *camera.project(Eigen::Vector3d(-2.5, 1.5, 0));
    cv::Scalar mean, sd;
    cv::meanStdDev(image(cv::Rect(static_cast<int>(px.x()) - 20, static_cast<int>(px.y()) - 20, 40, 40)),
                   mean, sd);
    return sd[1];
  };
  EXPECT_LT(carpetSpread(s), 0.6);
  s.appearance.carpet_fibre = 0.08;
  EXPECT_GT(carpetSpread(s), 2.0);

  // Shot noise: variance proportional to the signal (k per DN), between two frames.
  ScenarioConfig n = plain();
  n.appearance.shot_noise = 2.0;
  const cv::Mat a = render(n, {}, 1), b = render(n, {}, 2);
  cv::Mat diff;
  cv::subtract(a, b, diff, cv::noArray(), CV_32F);
  const cv::Rect patch(300, 230, 40, 40);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff(patch), mean, sd);
  const cv::Scalar level = cv::mean(a(patch));
  // Var(a - b) = 2 k level (plus 2 / 12 of 8-bit rounding).
  EXPECT_NEAR(sd[1] * sd[1] / (2 * 2.0 * level[1] + 2.0 / 12), 1.0, 0.15);
}

TEST(Appearance, ColourTemperatureWarmsAndTheLensBlurs) {
  ScenarioConfig s = plain();
  const cv::Mat neutral = render(s, {});
  s.appearance.color_temperature = 3000;
  const cv::Mat warm = render(s, {});
  const cv::Scalar n = cv::mean(neutral), w = cv::mean(warm);
  EXPECT_GT(w[2] / w[1], 1.2 * n[2] / n[1]);  // more red
  EXPECT_LT(w[0] / w[1], 0.8 * n[0] / n[1]);  // less blue

  // Blur: the steepest step across the lines falls.
  const auto steepest = [](const cv::Mat& image) {
    cv::Mat grey, grad;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    cv::Sobel(grey, grad, CV_32F, 1, 0);
    double lo, hi;
    cv::minMaxLoc(cv::abs(grad), &lo, &hi);
    return hi;
  };
  ScenarioConfig b = plain();
  b.appearance.lens_blur = 1.5;
  EXPECT_LT(steepest(render(b, {})), 0.6 * steepest(neutral));
}

TEST(Appearance, WideAngleTiltedCameraAndTheCamerasOwnDemosaic) {
  ScenarioConfig s = plain();
  s.lens.k1 = -0.3;
  s.lens.k2 = 0.08;
  s.lens.tilt_deg = 5;
  const CameraModel camera = cameraOf(s);
  EXPECT_DOUBLE_EQ(camera.intrinsics().dist[0], -0.3);
  const Eigen::Vector3d optical_axis = camera.fieldTCamera().linear().col(2);
  const double from_down = std::acos(-optical_axis.z()) * 180 / M_PI;
  // 5 degrees, plus or minus the built-in camera's mounting error (~1 degree).
  EXPECT_NEAR(from_down, 5.0, 1.2);

  s.sensor.bayer = "rggb";
  s.appearance.demosaic = true;
  const FieldRenderer renderer(camera, kField, kPatterns, s);
  EXPECT_EQ(renderer.encoding(), "bgr8");
  RenderedFrame out;
  renderer.render(oneRobot(), 0, out);
  EXPECT_EQ(out.image.type(), CV_8UC3);
}

// The ball as a sphere lit by the lamps: darker towards its rim, brighter where a lamp
// shines on it, and with gloss a pale highlight where it mirrors a lamp towards the camera.
TEST(Appearance, TheBallIsASphereLitByTheLampsWithItsHighlights) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ(), aside = Eigen::Vector3d::UnitX();
  {
    AppearanceConfig none;
    const BallLight overhead(LampSet(none, kField, 1), {}, Eigen::Vector3d(0, 0, 0.0215));
    EXPECT_NEAR(overhead.diffuse(up), 1.0, 1e-12);
    EXPECT_NEAR(overhead.diffuse(aside), BallLight::kIndirect, 1e-12);
    EXPECT_NEAR(overhead.specular(up, up, 20), 1.0, 1e-12);
    EXPECT_LT(overhead.specular(Eigen::Vector3d(1, 0, 1).normalized(), up, 20), 0.05);
  }
  AppearanceConfig a;
  a.lamps = 3;
  const LampSet lamps(a, kField, 7);
  const Eigen::Vector3d ball(1.0, -0.5, 0.0215);
  const BallLight light(lamps, {}, ball);
  EXPECT_NEAR(light.diffuse(up), 1.0, 1e-9) << "the top gets the light of a horizontal surface";
  const Lamp& l = lamps.lamp(0);
  const Eigen::Vector3d towards = (Eigen::Vector3d(l.x, l.y, ball.z()) - ball).normalized();
  const Eigen::Vector3d side = (up + towards).normalized(), far_side = (up - towards).normalized();
  EXPECT_GT(light.diffuse(side), light.diffuse(far_side) + 0.02);
  // Dimmed lamp 0 lights its side less.
  const BallLight dimmed(lamps, {0.2, 1.0, 1.0}, ball);
  EXPECT_LT(dimmed.diffuse(side) - dimmed.diffuse(far_side), light.diffuse(side) - light.diffuse(far_side));

  // Rendered, under the camera (light from above: no lamps): the rim darker, the middle pale.
  ScenarioConfig s = plain();
  s.width = 1280;
  s.height = 1024;
  const CameraModel camera = cameraOf(s);
  SceneState scene;
  BallState b;
  b.x = camera.cameraCentre().x();
  b.y = camera.cameraCentre().y();
  scene.balls.push_back(b);
  const Eigen::Vector2d centre = *camera.project(Eigen::Vector3d(b.x, b.y, b.z));
  const double radius_px = (*camera.project(Eigen::Vector3d(b.x + 0.0215, b.y, b.z)) - centre).norm();
  ASSERT_GT(radius_px, 4.0);
  const Eigen::Vector2d rim = centre + Eigen::Vector2d(0.7 * radius_px, 0);
  auto rimOverCentre = [&](const cv::Mat& image) {
    return meanAround(image, rim, 0)[1] / meanAround(image, centre, 0)[1];  // green
  };
  const cv::Mat even = render(s, scene);
  s.appearance.ball_shading = 1;
  const cv::Mat shaded = render(s, scene);
  EXPECT_LT(rimOverCentre(shaded), rimOverCentre(even) - 0.1);
  s.appearance.ball_gloss = 1;
  const cv::Mat glossy = render(s, scene);
  // Orange has no blue: the highlight's white brings it, in the middle only.
  EXPECT_GT(meanAround(glossy, centre, 0)[0], meanAround(shaded, centre, 0)[0] + 40);
  EXPECT_LT(meanAround(glossy, rim, 0)[0], meanAround(shaded, rim, 0)[0] + 15);
}
