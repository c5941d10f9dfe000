// calibrate_field end to end on make_scenario's camera_info.yaml and field_points.yaml
// (both cameras, 640x512): the written camera_pose.yaml equals the simulator's camera
// (< 1 mm, < 0.1°), the per-point errors and the RMS are printed, and bad input gives a
// non-zero exit with a message naming the problem.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "soccer_vision/common/camera_info_yaml.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/field_geometry.h"
#include "support/run_tool.h"

using namespace soccer_vision;

namespace {

const std::string kDir = ::testing::TempDir() + "/calibrate_field_test";

using soccer_vision::test::ToolRun;

ToolRun run(const std::string& args) { return soccer_vision::test::runTool(CALIBRATE_FIELD_BIN, args); }

class CalibrateField : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_EQ(std::system(("rm -rf " + kDir + " && mkdir -p " + kDir).c_str()), 0);
    const std::string cmd =
        std::string(MAKE_SCENARIO_BIN) + " --preset " + SOCCER_VISION_SOURCE_DIR +
        "/config/scenarios/even_static.yaml --frames 1 --width 640 --height 512 --cameras 0,1 --out " + kDir +
        "/s.bag > /dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
};

double rotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

}  // namespace

TEST_F(CalibrateField, RecoversBothSimulatorCamerasFromMakeScenarioFiles) {
  const FieldGeometry field;
  for (int cam : {0, 1}) {
    const std::string c = "_camera_" + std::to_string(cam);
    const std::string out = kDir + "/camera_pose" + c + ".yaml";
    const ToolRun r = run("--camera-info " + kDir + "/camera_info" + c + ".yaml --points " + kDir +
                          "/field_points" + c + ".yaml --out " + out + " --camera-id " + std::to_string(cam));
    ASSERT_EQ(r.status, 0) << r.output;
    std::printf("%s", r.output.c_str());
    const auto points = loadFieldCorrespondences(kDir + "/field_points" + c + ".yaml");
    ASSERT_GE(points.size(), 8u);
    // A row per point, then the RMS.
    EXPECT_NE(r.output.find(std::to_string(points.size() - 1) + " "), std::string::npos);
    EXPECT_NE(r.output.find("RMS"), std::string::npos);

    const CameraPoseFile pose = loadCameraPoseFile(out);
    const CameraModel truth = CameraModel::defaultCamera(field, cam, 640, 512);
    EXPECT_LT((pose.field_T_camera.translation() - truth.fieldTCamera().translation()).norm(), 0.001);
    EXPECT_LT(rotationErrorDeg(pose.field_T_camera, truth.fieldTCamera()), 0.1);
    EXPECT_LT(pose.rms_error_px, 0.01);  // the pixels are exact up to the file's 10 digits
    ASSERT_TRUE(pose.camera_id);
    EXPECT_EQ(*pose.camera_id, cam);
    EXPECT_EQ(pose.child_frame_id, "camera_" + std::to_string(cam) + "_optical");
    // The pose belongs to that camera_info and builds the same camera model.
    const CameraIntrinsics k = loadCameraInfoYaml(kDir + "/camera_info" + c + ".yaml");
    const CameraModel model = cameraModelFromPose(pose, k, out);
    EXPECT_LT((*model.project({-0.2 + cam * 0.4, 0.7, 0.15}) - *truth.project({-0.2 + cam * 0.4, 0.7, 0.15}))
                  .norm(),
              0.01);
  }
}

TEST_F(CalibrateField, BadInputGivesNonZeroExitAndAClearMessage) {
  const std::string info = kDir + "/camera_info.yaml", points = kDir + "/field_points.yaml",
                    out = kDir + "/bad_out.yaml";
  // Too few points.
  const auto all = loadFieldCorrespondences(points);
  writeTextFile(kDir + "/three.yaml", toYaml(std::vector<FieldCorrespondence>(all.begin(), all.begin() + 3)));
  ToolRun r = run("--camera-info " + info + " --points " + kDir + "/three.yaml --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("at least 4"), std::string::npos) << r.output;
  // Collinear points: the landmarks on the half-way line (x = 0).
  std::vector<FieldCorrespondence> line;
  for (const auto& p : all) {
    if (std::abs(p.field.x()) < 1e-9) line.push_back(p);
  }
  ASSERT_GE(line.size(), 4u);
  writeTextFile(kDir + "/line.yaml", toYaml(line));
  r = run("--camera-info " + info + " --points " + kDir + "/line.yaml --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("collinear"), std::string::npos) << r.output;
  // Corrupt files name themselves.
  writeTextFile(kDir + "/corrupt.yaml", "points: [ {pixel: [1, 2], field: \n");
  r = run("--camera-info " + info + " --points " + kDir + "/corrupt.yaml --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("corrupt.yaml"), std::string::npos) << r.output;
  r = run("--camera-info " + kDir + "/corrupt.yaml --points " + points + " --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("corrupt.yaml"), std::string::npos) << r.output;
  r = run("--camera-info " + kDir + "/missing.yaml --points " + points + " --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("missing.yaml"), std::string::npos) << r.output;
  // Wrong correspondences (pixels of one camera, intrinsics fine, field points shuffled).
  auto shuffled = all;
  std::swap(shuffled[0].field, shuffled[shuffled.size() / 2].field);
  std::swap(shuffled[1].field, shuffled[shuffled.size() - 1].field);
  writeTextFile(kDir + "/shuffled.yaml", toYaml(shuffled));
  r = run("--camera-info " + info + " --points " + kDir + "/shuffled.yaml --out " + out);
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_NE(r.output.find("exceeds --max-rms"), std::string::npos) << r.output;
  // Arguments.
  r = run("--points " + points + " --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--camera-info"), std::string::npos);
  r = run("--camera-info " + info + " --points " + points + " --out " + out + " --max-rms abc");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--max-rms: Value abc"), std::string::npos) << r.output;
  EXPECT_EQ(std::system(("test -e " + out).c_str()) == 0, false) << "no pose must be written on failure";
}

// From the field lines of make_scenario's frame of camera 0 (1280x1024, k1 -0.12) and 4
// corners of its half clicked 3 px off: with the true intrinsics; without distortion the
// tool refuses and advises --estimate-intrinsics; with it (focal length kept) it writes the
// pose and a camera_info whose k1 is the simulator's.
TEST(CalibrateFieldFromLines, PoseAndDistortionFromOneFrameAndFourCorners) {
  const std::string dir = kDir + "_lines";
  ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
  const std::string cmd = std::string(MAKE_SCENARIO_BIN) + " --preset " + SOCCER_VISION_SOURCE_DIR +
                          "/config/scenarios/even_static.yaml --frames 1 --cameras 0 --out " + dir +
                          "/s.bag > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const FieldGeometry field;
  const CameraModel truth = CameraModel::defaultCamera(field, 0);
  std::string corners;
  int sign = 1;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(-4.5, -3, 0), Eigen::Vector3d(0, -3, 0),
                                   Eigen::Vector3d(0, 3, 0), Eigen::Vector3d(-4.5, 3, 0)}) {
    const Eigen::Vector2d px = *truth.project(c) + Eigen::Vector2d(3.0 * sign, -3.0);
    sign = -sign;
    corners += (corners.empty() ? "" : ",") + std::to_string(px.x()) + "," + std::to_string(px.y());
  }
  const std::string image = dir + "/first_frame.png", info = dir + "/camera_info.yaml";
  ASSERT_EQ(std::system(("test -f " + image + " && test -f " + info).c_str()), 0) << "make_scenario's files";
  auto expectPose = [&](const std::string& out) {
    const CameraPoseFile pose = loadCameraPoseFile(out);
    const double mm = 1000 * (pose.field_T_camera.translation() - truth.fieldTCamera().translation()).norm();
    const double deg = rotationErrorDeg(pose.field_T_camera, truth.fieldTCamera());
    std::printf("[ calibrate_field --image ] %s: %.2f mm, %.4f deg, RMS %.3f px\n", out.c_str(), mm, deg,
                pose.rms_error_px);
    EXPECT_LT(mm, 10.0);
    EXPECT_LT(deg, 0.2);
    EXPECT_LE(pose.rms_error_px, 0.5);
  };

  const ToolRun known = run("--image " + image + " --camera-info " + info + " --corners " + corners +
                            " --out " + dir + "/pose.yaml");
  ASSERT_EQ(known.status, 0) << known.output;
  expectPose(dir + "/pose.yaml");

  // The same camera believed distortion-free.
  CameraIntrinsics k = loadCameraInfoYaml(info);
  ASSERT_NEAR(k.dist[0], -0.12, 1e-9);
  k.dist = {};
  saveCameraInfoYaml(dir + "/no_distortion.yaml", k, "camera_0");
  const ToolRun refused = run("--image " + image + " --camera-info " + dir +
                              "/no_distortion.yaml --corners " + corners + " --out " + dir + "/refused.yaml");
  EXPECT_EQ(refused.status, 3) << refused.output;
  EXPECT_NE(refused.output.find("intrinsics likely off; try --estimate-intrinsics"), std::string::npos)
      << refused.output;
  EXPECT_NE(system(("test -f " + dir + "/refused.yaml").c_str()), 0) << "nothing written";

  const ToolRun estimated =
      run("--image " + image + " --camera-info " + dir + "/no_distortion.yaml --corners " + corners +
          " --estimate-intrinsics --fix-focal-length --out " + dir + "/estimated.yaml");
  ASSERT_EQ(estimated.status, 0) << estimated.output;
  std::printf("%s", estimated.output.c_str());
  expectPose(dir + "/estimated.yaml");
  const CameraIntrinsics fitted = loadCameraInfoYaml(dir + "/estimated.camera_info.yaml");
  EXPECT_NEAR(fitted.dist[0], -0.12, 0.01);
  EXPECT_DOUBLE_EQ(fitted.fx, k.fx);

  // Usage: a start is needed; --fix-focal-length needs --camera-info.
  EXPECT_EQ(run("--image " + image + " --camera-info " + info + " --out " + dir + "/x.yaml").status, 2);
  EXPECT_EQ(run("--image " + image + " --estimate-intrinsics --fix-focal-length --corners " + corners +
                " --out " + dir + "/x.yaml")
                .status,
            2);
}
