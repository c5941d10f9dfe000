// Field calibration core: camera model round trips, the pose solver on exact and noisy
// correspondences and on degenerate input, camera_pose.yaml and camera_info.yaml.
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "soccer_vision/calibration/camera_pose_solver.h"
#include "soccer_vision/common/camera_info_yaml.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/simulation/calibration_samples.h"

using namespace soccer_vision;

namespace {

const FieldGeometry kField;

// A camera off to the side, tilted 35° and rolled, with tangential distortion and k3:
// nothing like the default cameras, so that the solver cannot lean on their symmetry.
CameraModel tiltedCamera() {
  CameraIntrinsics k;
  k.width = 1024;
  k.height = 768;
  k.fx = 700;
  k.fy = 705;
  k.cx = 515.2;
  k.cy = 380.7;
  k.dist = {-0.2, 0.05, 0.001, -0.0015, -0.004};
  Eigen::Matrix3d down;
  down.col(0) = Eigen::Vector3d::UnitY();
  down.col(1) = Eigen::Vector3d::UnitX();
  down.col(2) = -Eigen::Vector3d::UnitZ();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() =
      (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.61, Eigen::Vector3d::UnitY()))
          .toRotationMatrix() *
      down;
  pose.translation() = Eigen::Vector3d(-5.5, 0.4, 3.2);
  return CameraModel(k, pose);
}

double rotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

std::vector<FieldCorrespondence> pointsOf(const CameraModel& camera,
                                          const std::vector<Eigen::Vector3d>& field) {
  std::vector<FieldCorrespondence> out;
  for (const auto& p : field) {
    const auto px = camera.project(p);
    if (px && camera.inImage(*px, 5)) out.push_back({*px, p});
  }
  return out;
}

// Correspondences seen at given pixels, on planes of given heights.
std::vector<FieldCorrespondence> pointsAtPixels(const CameraModel& camera,
                                                const std::vector<Eigen::Vector3d>& uvz) {
  std::vector<FieldCorrespondence> out;
  for (const auto& p : uvz) {
    const Eigen::Vector2d px(p.x(), p.y());
    out.push_back({px, *camera.pixelToField(px, p.z())});
  }
  return out;
}

}  // namespace

TEST(CameraModelRoundTrip, PixelToFieldToPixelAtCarpetBallAndMarkerHeights) {
  for (const CameraModel& cam :
       {CameraModel::defaultCamera(kField, 0), CameraModel::defaultCamera(kField, 1), tiltedCamera()}) {
    double worst = 0;
    int n = 0;
    for (double z : {0.0, 0.0215, 0.15}) {
      for (double u = 0; u < cam.width(); u += 53) {
        for (double v = 0; v < cam.height(); v += 47) {
          const auto p = cam.pixelToField({u, v}, z);
          ASSERT_TRUE(p) << u << " " << v;
          EXPECT_NEAR(p->z(), z, 1e-9);
          const auto back = cam.project(*p);
          ASSERT_TRUE(back);
          worst = std::max(worst, (*back - Eigen::Vector2d(u, v)).norm());
          ++n;
        }
      }
    }
    EXPECT_GT(n, 600);
    EXPECT_LT(worst, 1e-6);
  }
}

TEST(CameraPoseSolver, RecoversTheDefaultCamerasFromExactLandmarks) {
  for (int index : {0, 1}) {
    const CameraModel truth = CameraModel::defaultCamera(kField, index);
    const auto points = fieldCorrespondences(truth, kField);
    ASSERT_GE(points.size(), 8u);
    const CameraPoseSolution s = solveCameraPose(truth.intrinsics(), points);
    const double dt = (s.field_T_camera.translation() - truth.fieldTCamera().translation()).norm();
    const double dr = rotationErrorDeg(s.field_T_camera, truth.fieldTCamera());
    std::printf(
        "[ exact, camera %d ] %zu points: position error %.2e m, rotation error %.2e deg, RMS %.2e px\n",
        index, points.size(), dt, dr, s.rms_px);
    EXPECT_LT(dt, 0.001);
    EXPECT_LT(dr, 0.1);
    EXPECT_LT(s.rms_px, 1e-4);
    ASSERT_EQ(s.errors_px.size(), points.size());
  }
}

TEST(CameraPoseSolver, RecoversATiltedCameraFromFourCoplanarOrNonCoplanarPoints) {
  const CameraModel truth = tiltedCamera();
  // Exactly 4 carpet points (the minimum; IPPE), then points at several heights (SQPnP).
  const auto four = pointsAtPixels(truth, {{100, 80, 0}, {950, 120, 0}, {900, 700, 0}, {60, 650, 0}});
  const auto mixed = pointsAtPixels(
      truth,
      {{100, 80, 0}, {950, 120, 0.15}, {900, 700, 0.3}, {60, 650, 0.0215}, {500, 400, 0.5}, {300, 200, 0.1}});
  for (const auto& points : {four, mixed}) {
    const CameraPoseSolution s = solveCameraPose(truth.intrinsics(), points);
    EXPECT_LT((s.field_T_camera.translation() - truth.fieldTCamera().translation()).norm(), 0.001);
    EXPECT_LT(rotationErrorDeg(s.field_T_camera, truth.fieldTCamera()), 0.1);
    EXPECT_LT(s.max_px, 1e-4);
  }
}

// 0.5 px Gaussian noise on every pixel: the RMS residual is the noise (less the 6 degrees
// of freedom fitted), the pose is off by millimetres, and marker positions projected
// through the solved camera land within about a pixel of the truth (worst at the corners).
TEST(CameraPoseSolver, NoisyCorrespondencesGiveASensibleError) {
  const CameraModel truth = CameraModel::defaultCamera(kField, 0);
  const auto exact = fieldCorrespondences(truth, kField);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5);
  double worst_dt = 0, worst_dr = 0, worst_px = 0, rms_sum = 0;
  const int trials = 20;
  for (int t = 0; t < trials; ++t) {
    auto points = exact;
    for (auto& p : points) p.pixel += Eigen::Vector2d(noise(rng), noise(rng));
    const CameraPoseSolution s = solveCameraPose(truth.intrinsics(), points);
    worst_dt =
        std::max(worst_dt, (s.field_T_camera.translation() - truth.fieldTCamera().translation()).norm());
    worst_dr = std::max(worst_dr, rotationErrorDeg(s.field_T_camera, truth.fieldTCamera()));
    rms_sum += s.rms_px;
    const CameraModel solved = s.model();
    for (double x = -4.5; x <= 0.3; x += 0.4) {
      for (double y = -3.0; y <= 3.0; y += 0.5) {
        const Eigen::Vector3d p(x, y, 0.15);
        worst_px = std::max(worst_px, (*solved.project(p) - *truth.project(p)).norm());
      }
    }
  }
  const double dof = std::sqrt((2.0 * exact.size() - 6) / (2.0 * exact.size()));
  std::printf(
      "[ 0.5 px noise ] %zu points, %d trials: mean RMS %.3f px (expected %.3f), worst position error "
      "%.1f mm, rotation %.3f deg, marker reprojection %.3f px\n",
      exact.size(), trials, rms_sum / trials, 0.5 * std::sqrt(2.0) * dof, 1000 * worst_dt, worst_dr,
      worst_px);
  EXPECT_NEAR(rms_sum / trials, 0.5 * std::sqrt(2.0) * dof, 0.12);
  EXPECT_LT(worst_dt, 0.03);
  EXPECT_LT(worst_dr, 0.3);
  EXPECT_LT(worst_px, 1.5);
}

TEST(CameraPoseSolver, RejectsDegenerateInputWithClearMessages) {
  const CameraModel cam = CameraModel::defaultCamera(kField, 0);
  const auto points = fieldCorrespondences(cam, kField);
  auto message = [&](const std::vector<FieldCorrespondence>& p, const CameraIntrinsics& k) -> std::string {
    try {
      solveCameraPose(k, p);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  const auto k = cam.intrinsics();
  EXPECT_NE(message({points.begin(), points.begin() + 3}, k).find("at least 4"), std::string::npos);
  EXPECT_NE(message({}, k).find("at least 4"), std::string::npos);
  const auto line = pointsOf(cam, {{-3, -1, 0}, {-2.5, -0.5, 0}, {-2, 0, 0}, {-1.5, 0.5, 0}, {-1, 1, 0}});
  ASSERT_EQ(line.size(), 5u);
  EXPECT_NE(message(line, k).find("collinear"), std::string::npos);
  auto same = points;
  for (auto& p : same) p = points.front();
  EXPECT_NE(message(same, k).find("must be distinct"), std::string::npos);
  // 4 points of which only 3 are distinct once passed.
  const auto tilted = tiltedCamera();
  auto three = pointsAtPixels(tilted, {{100, 80, 0}, {950, 120, 0}, {900, 700, 0}, {60, 650, 0}});
  three[3] = three[1];
  EXPECT_NE(message(three, tilted.intrinsics()).find("correspondences 1 and 3 have the same field point"),
            std::string::npos)
      << message(three, tilted.intrinsics());
  auto nan = points;
  nan[2].pixel.x() = std::nan("");
  EXPECT_NE(message(nan, k).find("non-finite"), std::string::npos);
  auto inf = points;
  inf[1].field.z() = INFINITY;
  EXPECT_NE(message(inf, k).find("non-finite"), std::string::npos);
  CameraIntrinsics no_focal = k;
  no_focal.fx = 0;
  EXPECT_NE(message(points, no_focal).find("focal"), std::string::npos);
}

TEST(CameraPoseFile, RoundTripAndSanityChecks) {
  const CameraModel cam = tiltedCamera();
  CameraPoseFile f;
  f.camera_id = 1;
  f.child_frame_id = "camera_1_optical";
  f.field_T_camera = cam.fieldTCamera();
  f.rms_error_px = 0.123;
  f.points = 17;
  f.intrinsics = cam.intrinsics();
  const std::string path = ::testing::TempDir() + "/camera_pose_test.yaml";
  saveCameraPoseFile(path, f);
  const CameraPoseFile g = loadCameraPoseFile(path);
  ASSERT_TRUE(g.camera_id);
  EXPECT_EQ(*g.camera_id, 1);
  EXPECT_EQ(g.frame_id, "field");
  EXPECT_EQ(g.child_frame_id, "camera_1_optical");
  EXPECT_LT((g.field_T_camera.translation() - f.field_T_camera.translation()).norm(), 1e-9);
  EXPECT_LT(rotationErrorDeg(g.field_T_camera, f.field_T_camera), 1e-7);
  EXPECT_DOUBLE_EQ(g.rms_error_px, 0.123);
  EXPECT_EQ(g.points, 17);
  EXPECT_EQ(g.intrinsics.width, 1024);
  EXPECT_EQ(g.intrinsics.height, 768);
  const CameraModel back = cameraModelFromPose(g, cam.intrinsics(), path);
  const Eigen::Vector3d seen = *cam.pixelToField({512, 384}, 0.15);
  EXPECT_LT((*back.project(seen) - *cam.project(seen)).norm(), 1e-6);

  // The same pose with a camera of another resolution or focal length is refused.
  CameraIntrinsics other = cam.intrinsics();
  other.width = 1280;
  EXPECT_THROW(checkIntrinsicsMatch(g, other, path), std::runtime_error);
  other = cam.intrinsics();
  other.fx *= 1.01;
  EXPECT_THROW(checkIntrinsicsMatch(g, other, path), std::runtime_error);

  // Optional keys may be absent; corrupt or incomplete files name the file.
  const CameraPoseFile minimal = parseCameraPoseFile(
      "translation: {x: 1, y: 2, z: 3}\nrotation: {x: 0, y: 0, z: 0, w: 1}\n"
      "intrinsics: {width: 640, height: 480, fx: 500, fy: 500, cx: 319.5, cy: 239.5}\n",
      "minimal.yaml");
  EXPECT_FALSE(minimal.camera_id);
  EXPECT_EQ(minimal.field_T_camera.translation(), Eigen::Vector3d(1, 2, 3));
  auto error = [](const std::string& text) -> std::string {
    try {
      parseCameraPoseFile(text, "broken_pose.yaml");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  for (const std::string& bad :
       {std::string("translation: {x: 1, y: [2\n"), std::string("- just a list\n"),
        std::string("translation: {x: 1, y: 2, z: 3}\nrotation: {x: 0, y: 0, z: 0, w: 1}\n"),
        std::string("translation: {x: 1, y: 2}\nrotation: {x: 0, y: 0, z: 0, w: 1}\n"
                    "intrinsics: {width: 640, height: 480, fx: 500, fy: 500, cx: 319.5, cy: 239.5}\n"),
        std::string("translation: {x: 1, y: 2, z: 3}\nrotation: {x: 0, y: 0, z: 0.5, w: 0.5}\n"
                    "intrinsics: {width: 640, height: 480, fx: 500, fy: 500, cx: 319.5, cy: 239.5}\n"),
        std::string("translation: {x: 1, y: 2, z: abc}\nrotation: {x: 0, y: 0, z: 0, w: 1}\n"
                    "intrinsics: {width: 640, height: 480, fx: 500, fy: 500, cx: 319.5, cy: 239.5}\n")}) {
    const std::string m = error(bad);
    EXPECT_NE(m.find("broken_pose.yaml"), std::string::npos) << bad << " -> '" << m << "'";
  }
  EXPECT_THROW(loadCameraPoseFile(::testing::TempDir() + "/does_not_exist.yaml"), std::runtime_error);
}

TEST(CameraInfoYaml, ReadsTheStandardCalibrationFile) {
  const std::string text =
      "image_width: 640\nimage_height: 512\ncamera_name: camera_0\n"
      "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [400, 0, 319.75, 0, 401, 255.75, 0, 0, 1]\n"
      "distortion_model: plumb_bob\n"
      "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [-0.12, 0.02, 0.001, 0.002, 0]\n"
      "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"
      "projection_matrix:\n  rows: 3\n  cols: 4\n  data: [400, 0, 319.75, 0, 0, 401, 255.75, 0, 0, 0, 1, "
      "0]\n";
  const CameraIntrinsics k = parseCameraInfoYaml(text, "ci.yaml");
  EXPECT_EQ(k.width, 640);
  EXPECT_EQ(k.height, 512);
  EXPECT_DOUBLE_EQ(k.fx, 400);
  EXPECT_DOUBLE_EQ(k.fy, 401);
  EXPECT_DOUBLE_EQ(k.cx, 319.75);
  EXPECT_DOUBLE_EQ(k.cy, 255.75);
  EXPECT_DOUBLE_EQ(k.dist[0], -0.12);
  EXPECT_DOUBLE_EQ(k.dist[3], 0.002);
  auto error = [](const std::string& t) -> std::string {
    try {
      parseCameraInfoYaml(t, "ci.yaml");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error("image_width: [\n").find("ci.yaml"), std::string::npos);
  EXPECT_NE(error("image_height: 5\n").find("image_width"), std::string::npos);
  std::string eq = text;
  eq.replace(eq.find("plumb_bob"), 9, "equidistant");
  EXPECT_NE(error(eq).find("equidistant"), std::string::npos);
  std::string no_k = text;
  no_k.replace(no_k.find("[400, 0, 319.75"), 4, "[0");
  EXPECT_NE(error(no_k).find("focal"), std::string::npos);
  // Sizes that would allocate gigabytes are refused up front.
  std::string huge = text;
  huge.replace(huge.find("image_width: 640"), 16, "image_width: 100000");
  EXPECT_NE(error(huge).find("ci.yaml: image size 100000x512 outside 1..16384"), std::string::npos)
      << error(huge);
}
