// detect: one image in, what the system sees out. The image goes through the same stages as
// a live frame (Segmenter over the colour table, then FrameIdentifier), and the tool prints
// and optionally writes what they found: the regions, the robots and balls, and the
// candidates identification rejected, by cause.
//
//   rosrun soccer_vision detect --image IMG --colors T.svct
//       [--camera-info C.yaml --camera-pose P.yaml] [--patterns NAME|FILE] [--field NAME|FILE]
//       [--json OUT.json] [--overlay OUT.png]
//
// Without --camera-pose, identification assumes a camera looking straight down from 4 m
// over the image centre (the built-in synthetic camera's height; intrinsics from
// --camera-info or f = 800 px per 1280 px of width): robots of a roughly overhead camera
// are found, but field positions would be made up, so x, y and theta are null then.
//
// Exit status: 0 on success; 2 for bad arguments, unreadable or invalid files, an image
// whose size differs from the camera's, or an unwritable output.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "frame_json.h"
#include "soccer_vision/common/camera_info_yaml.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/class_colors.h"
#include "soccer_vision/common/field_markings_image.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;
using json = nlohmann::json;

namespace {

struct Options {
  std::string image, colors, camera_info, camera_pose, patterns = "two_tag", field = "div_b", json_out,
                                                       overlay;
};

// Straight down from this height [m] over the image centre when no pose is given.
constexpr double kAssumedHeight = 4.0;

sv::CameraModel assumedOverheadCamera(const sv::CameraIntrinsics& k) {
  // Optical frame looking down: x_opt (u) = +y_field, y_opt (v) = +x_field, z_opt = -z_field.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = Eigen::Vector3d::UnitY();
  pose.linear().col(1) = Eigen::Vector3d::UnitX();
  pose.linear().col(2) = -Eigen::Vector3d::UnitZ();
  pose.translation() = Eigen::Vector3d(0, 0, kAssumedHeight);
  return sv::CameraModel(k, pose);
}

sv::CameraIntrinsics assumedIntrinsics(int width, int height) {
  sv::CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 800.0 * width / 1280.0;
  k.cx = (width - 1) / 2.0;
  k.cy = (height - 1) / 2.0;
  return k;
}

cv::Scalar drawColor(sv::ColorClass c) {
  const cv::Vec3f a = sv::classAlbedo(c);
  const double scale = 255.0 / std::max({a[0], a[1], a[2], 1.0f});
  return cv::Scalar(a[0] * scale, a[1] * scale, a[2] * scale);
}

void drawOverlay(cv::Mat& canvas, const sv::SegmentationResult& seg, const sv::CameraFrameDetections& d,
                 const sv::CameraModel& camera, const sv::FieldGeometry& field, bool have_pose) {
  const double scale = std::max(1.0, canvas.cols / 1280.0);
  const int thin = std::max(1, static_cast<int>(std::lround(scale)));
  auto pt = [](const Eigen::Vector2d& p) { return cv::Point(cvRound(p.x()), cvRound(p.y())); };
  if (have_pose) {
    for (const auto& line : sv::projectFieldMarkings(camera, field, 0.02)) {
      for (std::size_t i = 1; i < line.size(); ++i)
        cv::line(canvas, pt(line[i - 1]), pt(line[i]), cv::Scalar(255, 0, 255), thin, cv::LINE_8);
    }
  }
  for (const sv::Region& r : seg.regions) cv::rectangle(canvas, r.bbox, drawColor(r.color), thin);
  for (const sv::RobotDetection& r : d.robots) {
    const cv::Scalar c = r.team == sv::Team::Blue ? cv::Scalar(255, 128, 0) : cv::Scalar(0, 220, 255);
    const int radius = static_cast<int>(std::lround(18 * scale));
    cv::circle(canvas, pt(r.pixel), radius, c, 2 * thin, cv::LINE_AA);
    if (r.heading_valid) {
      // The heading in the image: towards the pixel of a point 90 mm ahead on the field.
      const auto centre = camera.pixelToField(r.pixel, 0.0);
      const auto ahead = centre ? camera.project({centre->x() + 0.09 * std::cos(r.theta),
                                                  centre->y() + 0.09 * std::sin(r.theta), 0})
                                : std::nullopt;
      if (ahead) cv::line(canvas, pt(r.pixel), pt(*ahead), c, 2 * thin, cv::LINE_AA);
    }
    const std::string label =
        std::string(r.team == sv::Team::Blue ? "B" : "Y") + (r.id >= 0 ? std::to_string(r.id) : "?");
    cv::putText(canvas, label, pt(r.pixel) + cv::Point(radius, -radius), cv::FONT_HERSHEY_SIMPLEX,
                0.6 * scale, c, thin, cv::LINE_AA);
  }
  for (const sv::BallDetection& b : d.balls)
    cv::circle(canvas, pt(b.pixel), static_cast<int>(std::lround(10 * scale)), cv::Scalar(0, 0, 255),
               2 * thin, cv::LINE_AA);
}

int run(const Options& o) {
  const cv::Mat image = cv::imread(o.image, cv::IMREAD_COLOR);
  if (image.empty()) throw std::runtime_error(o.image + ": not a readable image");
  const auto table = std::make_shared<const sv::ColorTable>(sv::ColorTable::load(o.colors));
  const sv::PatternSet patterns = sv::patternSetByName(o.patterns);
  const sv::FieldGeometry field = sv::fieldGeometryByName(o.field);

  const sv::CameraIntrinsics k = o.camera_info.empty() ? assumedIntrinsics(image.cols, image.rows)
                                                       : sv::loadCameraInfoYaml(o.camera_info);
  if (k.width != image.cols || k.height != image.rows) {
    throw std::runtime_error(o.camera_info + ": camera is " + std::to_string(k.width) + "x" +
                             std::to_string(k.height) + ", " + o.image + " is " + std::to_string(image.cols) +
                             "x" + std::to_string(image.rows));
  }
  const bool have_pose = !o.camera_pose.empty();
  const sv::CameraModel camera =
      have_pose ? sv::cameraModelFromPose(sv::loadCameraPoseFile(o.camera_pose), k, o.camera_pose)
                : assumedOverheadCamera(k);

  sv::Segmenter segmenter;
  sv::SegmentationResult seg;
  segmenter.process(*sv::SegmentationModel::fromTable(table), image, sv::PixelLayout::Bgr, {}, seg);
  const sv::FrameIdentifier identifier(camera, patterns, field);
  const sv::CameraFrameDetections d = identifier.identify(seg.regions);

  json out = sv::detectionsJson(d, have_pose);
  out["blobs"] = sv::regionsJson(seg.regions);
  std::printf("%zu regions, %zu robots, %zu balls%s\n", seg.regions.size(), d.robots.size(), d.balls.size(),
              have_pose ? "" : " (no --camera-pose: image positions only)");
  for (const sv::RobotDetection& r : d.robots) {
    std::printf("  robot %-6s %3d  u %8.2f v %8.2f", std::string(sv::teamName(r.team)).c_str(), r.id,
                r.pixel.x(), r.pixel.y());
    if (have_pose) std::printf("  x %7.3f y %7.3f", r.x, r.y);
    if (have_pose && r.heading_valid) std::printf(" theta %7.2f deg", r.theta * 180 / M_PI);
    std::printf("  confidence %.3f\n", r.confidence);
  }
  for (const sv::BallDetection& b : d.balls) {
    std::printf("  ball         u %8.2f v %8.2f", b.pixel.x(), b.pixel.y());
    if (have_pose) std::printf("  x %7.3f y %7.3f", b.x, b.y);
    std::printf("  confidence %.3f\n", b.confidence);
  }
  std::printf("rejected: %s\n", d.rejections.summary().c_str());

  if (!o.json_out.empty()) {
    std::ofstream f(o.json_out);
    f << out.dump(2) << "\n";
    if (!f) throw std::runtime_error(o.json_out + ": cannot write");
    std::printf("wrote %s\n", o.json_out.c_str());
  }
  if (!o.overlay.empty()) {
    cv::Mat canvas = image.clone();
    drawOverlay(canvas, seg, d, camera, field, have_pose);
    bool ok = false;
    try {
      ok = cv::imwrite(o.overlay, canvas);
    } catch (const cv::Exception& e) {
      ok = false;
    }
    if (!ok)
      throw std::runtime_error(o.overlay + ": cannot write (a .png or .jpg path in an existing folder)");
    std::printf("wrote %s\n", o.overlay.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "detect: one image through segmentation and identification; prints (and writes as JSON and an "
      "overlay image) the regions, robots, balls and rejected candidates by cause",
      "detect"};
  app.add_option("--image", o.image, "Image file (BGR as read by OpenCV)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--colors", o.colors, "Colour table (.svct of calibrate_colors)")
      ->required()
      ->check(CLI::ExistingFile);
  auto* info =
      app.add_option("--camera-info", o.camera_info, "Camera intrinsics (ROS camera calibration YAML)")
          ->check(CLI::ExistingFile);
  app.add_option("--camera-pose", o.camera_pose,
                 "camera_pose.yaml of calibrate_field; without it x, y and theta are null")
      ->check(CLI::ExistingFile)
      ->needs(info);
  app.add_option("--patterns", o.patterns, "Marker pattern: two_tag, ssl, team_only or a pattern YAML")
      ->capture_default_str();
  app.add_option("--field", o.field, "Field geometry: div_b, div_a or a field YAML")->capture_default_str();
  app.add_option("--json", o.json_out, "Write the results as JSON here");
  app.add_option("--overlay", o.overlay, "Write the image with regions, robots, balls and field lines here");
  if (const auto status = soccer_vision::parseCommandLine(app, argc, argv)) return *status;
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::cerr << "detect: " << e.what() << "\n";
    return 2;
  }
}
