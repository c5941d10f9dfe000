// evaluate: the offline evaluation of a recording (paper §IV on our own data). Reads the
// cameras' image_raw + camera_info from a rosbag and runs the whole pipeline in-process on
// every frame (VisionPipeline: the nodelets' algorithms and decisions, deterministic:
// nothing depends on the clock), as fast as the machine allows, then scores the tracked
// output against ground truth (scoring.h, evaluation.h).
//
//   rosrun soccer_vision evaluate --bag FILE [--truth truth.jsonl]
//       [--colors T.svct[,T1.svct] | --samples S.yaml[,S1.yaml]
//        [--calibration-image P.png[,P1.png] | --calibration-frame N [--more-samples C:N:F[,...]]]]
//       [--field-points F.yaml[,F1.yaml] [--pose-from lines|points] | --camera-pose C.yaml[,C1.yaml]]
//       [--patterns NAME|FILE] [--field div_b|div_a|FILE]
//       [--cameras 0[,1]] [--frame-step N] [--window-side R] [--no-windows] [--no-ball-streaks]
//       [--skip-table2]
//       [--measurement-offset S[,S1]]
//       [--sweep] [--results out.jsonl] [--misses m.jsonl] [--trace t.jsonl]
//       [--json report.json] [--plots DIR]
//       [--markdown section.md [--title TEXT]]
//   rosbag-less:  evaluate --results-only --results results.jsonl (--truth truth.jsonl | --bag FILE)
//       [--json report.json] [--plots DIR]
//
// Lists take one entry per camera, in camera order. --measurement-offset: seconds after
// the capture stamp at which a frame's detections were measured (the Tracking nodelet's
// measurement_offset: exposure / 2 for stamps at the exposure start; one value for all
// cameras or one per camera). What is not given is taken from the
// files make_scenario writes beside the bag: truth.jsonl (when the bag has no ground-truth
// topics), samples_camera_<n>_frame_<i>.yaml (samples on frame i: the table is calibrated
// on all of those frames of the bag) or samples[_camera_<n>].yaml (on the first frame, or
// frame --calibration-frame),
// field_points[_camera_<n>].yaml. Without --calibration-image the samples are taken from
// the bag's frames themselves (for a Bayer camera: their quad colours, what the
// classifier reads). --more-samples CAMERA:FRAME:FILE: colours the calibration frame does
// not show, sampled on another frame (make_scenario's more_samples_<k>.yaml), merged as the
// calibration UI merges a second frame (keepUnsampledClasses). Colour tables are built with
// calibrate_colors' code (calibrateColorTable), camera poses with calibrate_field's (solveCameraPose, then by
// default refined on the field lines of the bag's first frame as calibrate_field --image
// --points does: fitCameraToFieldLines; --pose-from points: the points alone).
//
// Reports (printed; --json as one object): the measured rate (visible robots measured by
// their own frame's detections, the others by cause: measured_rate.h), robot/ball/all
// detection rate and precision,
// position and heading RMSE, identity switches and errors, frames processed and per
// second; Table II (time per stage with and without dynamic windows, same bag and frame
// step); with --sweep Table I (frame step 1-4 x window side 50/100/200/400 px: time,
// processed, global-search, window and failed frames, failure and success rates).
// --markdown FILE: the tables as a Markdown section beside the paper's (docs/evaluation.md
// is made of them: scripts/evaluate_presets).
// --plots DIR: trajectories.png (the first 20 s), position_error.png, stage_times.png,
// prediction_error.png (a run per frame step 1-4, from the sweep when there is one).
// Exit status: 0 done, 2 bad arguments or unreadable inputs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sys/stat.h>

#include "evaluate_report.h"
#include "evaluation_plots.h"
#include "frame_json.h"
#include "soccer_vision/calibration/camera_pose_solver.h"
#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/calibration/field_line_calibration.h"
#include "soccer_vision/common/bayer_encoding.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/evaluation/evaluation.h"
#include "soccer_vision/evaluation/measured_rate.h"
#include "soccer_vision/pipeline/vision_pipeline.h"
#include "soccer_vision/ros/bag_frames.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/tracking/result_recording.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

namespace {

struct Options {
  std::string bag, truth, results, misses, trace, json, plots, markdown, title, patterns = "two_tag",
                                                                                field = "div_b";
  std::vector<std::string> colors, samples, calibration_images, field_points, camera_poses;
  std::vector<std::string> more_samples;    // CAMERA:FRAME:FILE
  std::vector<double> measurement_offsets;  // [s]
  std::vector<int> cameras;
  int frame_step = 1, window_side = 200;
  int calibration_frame = 0;        // the bag frame --samples / samples.yaml are on
  std::string pose_from = "lines";  // with field points: "points" alone, or refined on the "lines"
  bool windows = true, table2 = true, sweep = false, results_only = false, online_calibration = false;
  bool ball_streaks = true;
};

// The options (docs/tools.md); which go together is checked by combinationProblem.
void addOptions(CLI::App& app, Options& o) {
  app.add_option("--bag", o.bag, "recording of make_scenario or of a camera (image_raw, camera_info)");
  app.add_option(
      "--truth", o.truth,
      "ground truth JSON Lines (default: the bag's ground-truth topics, else truth.jsonl beside it)");
  app.add_option("--results", o.results,
                 "write (or with --results-only read) the tracker's results, JSON Lines");
  app.add_option(
      "--misses", o.misses,
      "write every visible robot a frame did not measure (stamp, camera, robot, cause, pixel), JSON Lines");
  app.add_option("--trace", o.trace,
                 "write what the pipeline saw in every frame (regions, detections, rejections, tracks), JSON "
                 "Lines");
  app.add_option("--json", o.json, "write the report as JSON");
  app.add_option("--plots", o.plots, "write the report's figures (PNG) into this directory");
  app.add_option("--markdown", o.markdown, "write the report as a Markdown section");
  app.add_option("--title", o.title, "title of the Markdown section (default: the bag's path)");
  app.add_option("--patterns", o.patterns, "marker patterns: two_tag, ssl, team_only or a pattern file")
      ->capture_default_str();
  app.add_option("--field", o.field, "field geometry: div_b, div_a or a field YAML")->capture_default_str();
  app.add_option("--colors", o.colors, "colour table per camera (.svct), comma-separated")->delimiter(',');
  app.add_option("--samples", o.samples, "calibrate from colour samples per camera instead, comma-separated")
      ->delimiter(',');
  app.add_option("--calibration-image", o.calibration_images, "image per camera the samples are on (PNG)")
      ->delimiter(',');
  app.add_option("--calibration-frame", o.calibration_frame,
                 "bag frame the samples are on, without --calibration-image (make_scenario prints it)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option(
         "--more-samples", o.more_samples,
         "colours the calibration frame does not show, painted on another bag frame and merged as the "
         "calibration UI's second frame is (keepUnsampledClasses): CAMERA:FRAME:FILE, comma-separated")
      ->delimiter(',');
  app.add_option("--field-points", o.field_points, "field points per camera to solve its pose from")
      ->delimiter(',');
  app.add_option("--pose-from", o.pose_from,
                 "with field points: their pose refined on the field lines of the bag's first frame (lines, "
                 "as calibrate_field --image --points) or the points alone (points)")
      ->check(CLI::IsMember(std::vector<std::string>{"lines", "points"}))
      ->capture_default_str();
  app.add_option("--camera-pose", o.camera_poses, "camera pose file per camera instead")->delimiter(',');
  app.add_option("--measurement-offset", o.measurement_offsets,
                 "[s] per camera: where in its exposure a frame shows the objects")
      ->delimiter(',');
  app.add_option("--cameras", o.cameras, "camera ids to evaluate (default: every camera of the bag)")
      ->delimiter(',')
      ->check(CLI::Range(0, 255));
  app.add_option("--frame-step", o.frame_step, "process every N-th frame")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--window-side", o.window_side, "[px] search window side at 1280 px width")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_flag_callback(
      "--no-windows", [&o] { o.windows = false; }, "segment whole frames only");
  app.add_flag_callback(
      "--no-ball-streaks", [&o] { o.ball_streaks = false; },
      "no streak table in the ball's windows (its orange as the colour table's)");
  app.add_flag_callback(
      "--skip-table2", [&o] { o.table2 = false; }, "skip the run without search windows");
  app.add_flag("--sweep", o.sweep, "also run Table I: frame step 1-4 x window side 50-400 px");
  app.add_flag("--online-calibration", o.online_calibration,
               "refine each camera's colour table and light from its confirmed markers while running");
  app.add_flag("--results-only", o.results_only, "score --results against the truth, without running");
}

// Options that do not go together, or "" when they do.
std::string combinationProblem(const Options& o) {
  if (o.results_only) {
    if (o.results.empty()) return "--results-only needs --results FILE";
    if (o.truth.empty() && o.bag.empty()) return "--results-only needs --truth FILE or --bag FILE";
  } else if (o.bag.empty()) {
    return "--bag FILE is required";
  }
  if (!o.colors.empty() && !o.samples.empty()) return "give --colors or --samples, not both";
  if (!o.more_samples.empty() && (!o.colors.empty() || !o.calibration_images.empty()))
    return "--more-samples are on frames of the bag: not with --colors or --calibration-image";
  if (o.results_only && !o.misses.empty()) return "--misses needs a run of the pipeline, not --results-only";
  if (o.results_only && !o.trace.empty()) return "--trace needs a run of the pipeline, not --results-only";
  if (!o.field_points.empty() && !o.camera_poses.empty())
    return "give --field-points or --camera-pose, not both";
  return "";
}

bool fileExists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// Entry `index` of a per-camera list, else make_scenario's file beside the bag
// (<stem>_camera_<n><ext>, or <stem><ext> for the first camera); "" when neither exists.
std::string cameraFile(const std::vector<std::string>& given, std::size_t index, const std::string& flag,
                       const std::string& bag, const std::string& stem, const std::string& ext,
                       int camera_id) {
  if (!given.empty()) {
    if (index >= given.size())
      throw std::invalid_argument(flag + " has no entry for camera " + std::to_string(camera_id));
    return given[index];
  }
  const std::string dir = directoryOf(bag);
  const std::string per_camera = dir + "/" + stem + "_camera_" + std::to_string(camera_id) + ext;
  if (fileExists(per_camera)) return per_camera;
  if (index == 0 && fileExists(dir + "/" + stem + ext)) return dir + "/" + stem + ext;
  return "";
}

// make_scenario's calibration samples of a camera beside the bag:
// samples_camera_<n>_frame_<i>.yaml -> (i, path), by frame.
std::map<std::size_t, std::string> calibrationSamplesBeside(const std::string& bag, int camera_id) {
  const std::string prefix = "samples_camera_" + std::to_string(camera_id) + "_frame_";
  std::map<std::size_t, std::string> found;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(directoryOf(bag), ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || name.size() <= prefix.size() + 5 ||
        name.substr(name.size() - 5) != ".yaml")
      continue;
    const std::string index = name.substr(prefix.size(), name.size() - prefix.size() - 5);
    if (index.find_first_not_of("0123456789") == std::string::npos)
      found[std::stoul(index)] = entry.path().string();
  }
  return found;
}

// The sample files of one camera by the bag frame they describe: the ones given (on the
// first frame or the calibration image), else make_scenario's calibration frames, else its
// samples.yaml on the first frame. Empty with --colors (no calibration).
std::map<std::size_t, std::string> samplesByFrame(const Options& o, std::size_t index, int camera_id) {
  std::map<std::size_t, std::string> samples;
  if (!o.colors.empty()) return samples;
  if (o.samples.empty()) samples = calibrationSamplesBeside(o.bag, camera_id);
  if (samples.empty()) {
    const std::string file = cameraFile(o.samples, index, "--samples", o.bag, "samples", ".yaml", camera_id);
    if (file.empty()) {
      throw std::invalid_argument("camera " + std::to_string(camera_id) +
                                  ": no colour table (--colors) and no samples "
                                  "(--samples, or make_scenario's samples files beside the bag)");
    }
    samples[static_cast<std::size_t>(o.calibration_frame)] = file;
  }
  return samples;
}

// --more-samples of one camera: bag frame -> sample file.
std::map<std::size_t, std::string> moreSamples(const Options& o, int camera_id) {
  std::map<std::size_t, std::string> more;
  for (const std::string& entry : o.more_samples) {
    const auto first = entry.find(':'), second = entry.find(':', first + 1);
    const auto number = [&](std::size_t from, std::size_t to) {
      const std::string text = entry.substr(from, to - from);
      if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos)
        throw std::invalid_argument("--more-samples " + entry + ": expected CAMERA:FRAME:FILE");
      return std::stoul(text);
    };
    if (first == std::string::npos || second == std::string::npos || second + 1 >= entry.size())
      throw std::invalid_argument("--more-samples " + entry + ": expected CAMERA:FRAME:FILE");
    if (static_cast<int>(number(0, first)) == camera_id)
      more[number(first + 1, second)] = entry.substr(second + 1);
  }
  return more;
}

// One frame of the bag with the samples drawn on it, in the colours the classifier reads.
sv::CalibrationImage calibrationFrame(const Options& o,
                                      const std::map<std::size_t, sv::BagFrames::Image>& frames,
                                      std::size_t frame, const std::string& file, int camera_id) {
  sv::CalibrationImage image;
  image.samples = sv::loadColorSamples(file);
  const auto found = frames.find(frame);
  if (found == frames.end()) {
    throw std::invalid_argument(o.bag + ": camera " + std::to_string(camera_id) + " has no readable frame " +
                                std::to_string(frame) + " for " + file);
  }
  image.bgr = sv::classifiedColors(found->second.pixels, found->second.layout);
  return image;
}

// The colour table of one camera: given, or calibrated like calibrate_colors does from
// samples on frames of the bag (their quad colours for Bayer: what the classifier reads),
// with the colours of --more-samples merged in as the calibration UI merges a second frame,
// and calibrate_colors' warnings (clipped samples, the pattern's colours the table lacks).
std::shared_ptr<const sv::SegmentationModel> colorModel(
    const Options& o, const sv::PatternSet& patterns, const std::map<std::size_t, std::string>& samples,
    const std::map<std::size_t, std::string>& more, const std::map<std::size_t, sv::BagFrames::Image>& frames,
    std::size_t index, int camera_id) {
  if (!o.colors.empty()) {
    if (index >= o.colors.size())
      throw std::invalid_argument("--colors has no entry for camera " + std::to_string(camera_id));
    return sv::SegmentationModel::fromTable(
        std::make_shared<const sv::ColorTable>(sv::ColorTable::load(o.colors[index])));
  }
  std::vector<sv::CalibrationImage> images;
  std::string described;
  for (const auto& [frame, file] : samples) {
    sv::CalibrationImage image;
    if (!o.calibration_images.empty()) {
      image.samples = sv::loadColorSamples(file);
      if (index >= o.calibration_images.size()) {
        throw std::invalid_argument("--calibration-image has no entry for camera " +
                                    std::to_string(camera_id));
      }
      image.bgr = cv::imread(o.calibration_images[index], cv::IMREAD_COLOR);
      if (image.bgr.empty()) throw std::invalid_argument(o.calibration_images[index] + ": cannot read image");
    } else {
      image = calibrationFrame(o, frames, frame, file, camera_id);
    }
    images.push_back(std::move(image));
    described += (described.empty() ? "" : ", ") + std::to_string(frame);
  }
  std::printf("camera %d: colour table calibrated on %s (frame %s of the bag)\n", camera_id,
              o.calibration_images.empty() ? (std::to_string(images.size()) + " frame(s)").c_str()
                                           : o.calibration_images[index].c_str(),
              described.c_str());
  for (const auto& [frame, file] : more) {
    images.push_back(calibrationFrame(o, frames, frame, file, camera_id));
    images.back().unsampled_is_background = false;
    std::printf("camera %d: and %s on frame %zu of the bag (--more-samples)\n", camera_id,
                sv::sampledClassNames(images.back().samples).c_str(), frame);
  }
  auto table = std::make_shared<const sv::ColorTable>(sv::calibrateColorTable(images));
  for (const std::string& w : sv::calibrationWarnings(images, *table, &patterns))
    std::printf("camera %d: warning: %s\n", camera_id, w.c_str());
  return sv::SegmentationModel::fromTable(std::move(table));
}

// The bag's image as BGR at full resolution (a Bayer image demosaiced), as a camera shows it.
cv::Mat fullBgr(const sv::BagFrames::Image& image);

// Intrinsics from the bag's camera_info, the pose given or solved like calibrate_field: from
// the field points, refined on the field lines of `first` unless --pose-from points.
sv::CameraModel cameraModel(const Options& o, const sv::BagCamera& camera, std::size_t index,
                            const sv::BagFrames::Image& first, const sv::FieldGeometry& field) {
  if (!camera.has_info) throw std::invalid_argument(camera.ns + ": no camera_info in the bag");
  const sv::CameraIntrinsics intrinsics = sv::intrinsicsFromCameraInfo(camera.info);
  if (!o.camera_poses.empty()) {
    if (index >= o.camera_poses.size())
      throw std::invalid_argument("--camera-pose has no entry for camera " + std::to_string(camera.id));
    return sv::cameraModelFromPose(sv::loadCameraPoseFile(o.camera_poses[index]), intrinsics,
                                   o.camera_poses[index]);
  }
  const std::string points =
      cameraFile(o.field_points, index, "--field-points", o.bag, "field_points", ".yaml", camera.id);
  if (points.empty()) {
    throw std::invalid_argument("camera " + std::to_string(camera.id) +
                                ": no camera pose (--camera-pose) and no field "
                                "points (--field-points, or field_points.yaml beside the bag)");
  }
  const sv::CameraPoseSolution pose = sv::solveCameraPose(intrinsics, sv::loadFieldCorrespondences(points));
  std::printf("camera %d: pose solved from %s, reprojection RMS %.3f px (max %.3f px)\n", camera.id,
              points.c_str(), pose.rms_px, pose.max_px);
  if (o.pose_from == "points") return pose.model();
  // As calibrate_field --image --points: the clicks start the fit to the line pixels. A
  // fit calibrate_field would refuse (its --max-rms default, 1 px) leaves the clicked pose.
  const sv::LineRefinement refined = sv::refinePoseOnFieldLines(fullBgr(first), field, pose.model());
  if (!refined.fit) {
    std::printf("camera %d: pose from the points alone: the field lines' fit: %s\n", camera.id,
                refined.reason.c_str());
    return pose.model();
  }
  const sv::FieldLineFit& fit = *refined.fit;
  const Eigen::Vector3d moved = fit.camera.cameraCentre() - pose.model().cameraCentre();
  std::printf(
      "camera %d: pose refined on the field lines of frame 0: %d line pixels, across-line RMS %.3f px, "
      "camera centre moved %.1f mm%s%s\n",
      camera.id, fit.pixels_paired, fit.rms_px, 1000 * moved.norm(), refined.advice.empty() ? "" : "; ",
      refined.advice.c_str());
  return fit.camera;
}

cv::Mat fullBgr(const sv::BagFrames::Image& image) {
  return sv::bgrOfEncoding(image.pixels, sv::encodingForPixelLayout(image.layout));
}

// --- Runs --------------------------------------------------------------------

struct RunStats {
  sv::RunEvaluation evaluation;
  sv::MeasuredRateCounter measured;
  std::int64_t images = 0, processed = 0, global = 0, windowed = 0;
  std::vector<double> preprocessing, classification, recognition, tracking,
      total;                        // [ms] per processed frame
  double seconds = 0;               // pipeline time (bag reading excluded)
  std::uint32_t learned_cells = 0;  // online calibration: cells learned at the end, all cameras
};

struct Setup {
  const sv::BagFrames* bag = nullptr;
  std::vector<sv::PipelineCamera> cameras;
  sv::PatternSet patterns;
  sv::FieldGeometry field;
  const sv::TruthTimeline* truth = nullptr;
  sv::BagImageProblems problems;
};

// `results` and `trace`, when given, get a line per processed frame.
RunStats run(Setup& setup, const sv::VisionPipelineParams& params, sv::JsonLinesWriter* results,
             std::ostream* trace = nullptr) {
  sv::VisionPipeline pipeline(setup.cameras, setup.patterns, setup.field, params);
  RunStats s;
  std::map<int, std::int64_t> image_index;  // per camera: the bag's image number
  s.measured = sv::MeasuredRateCounter(setup.patterns);
  std::vector<int> ids;
  for (const auto& c : setup.cameras) ids.push_back(c.id);
  setup.problems = {};
  setup.bag->forEachImage(
      ids,
      [&](const sv::BagCamera& camera, const sensor_msgs::Image& msg, const cv::Mat& image,
          sv::PixelLayout layout) {
        ++s.images;
        const std::int64_t index = image_index[camera.id]++;
        const sv::PipelineCamera& pc = *pipeline.camera(camera.id);
        if (layout != pc.layout || image.cols != pc.model.width() || image.rows != pc.model.height()) {
          ++setup.problems.other_format;  // not what the camera's calibration was made for
          return;
        }
        const double stamp = msg.header.stamp.toSec();
        const auto t0 = Clock::now();
        const sv::PipelineFrame f = pipeline.process(camera.id, image, stamp);
        s.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        if (!f.processed) return;
        ++s.processed;
        (f.global_search ? s.global : s.windowed)++;
        s.preprocessing.push_back(f.times.preprocessing);
        s.classification.push_back(f.times.classification);
        s.recognition.push_back(f.times.recognition);
        s.tracking.push_back(f.times.tracking);
        s.total.push_back(f.times.total());
        const sv::FrameRecord record = sv::toFrameRecord(f.output);
        if (results) results->write(record);
        if (trace) {
          json line = sv::frameTraceJson(f, pipeline.tracker());
          line["image"] = index;
          *trace << line.dump() << "\n";
        }
        const sv::FrameRecord* truth = setup.truth ? setup.truth->at(stamp) : nullptr;
        if (!truth) {
          s.evaluation.addUnscored();
          return;
        }
        s.evaluation.add(*truth, record);
        std::vector<sv::MarkerRegionCentre> marker_regions;
        for (const sv::Region& r : f.regions) {
          // The ball's colour is no robot's: a region of it is no hint of a robot.
          if (sv::isRobotMarkerColor(r.color))
            marker_regions.push_back({Eigen::Vector2d(r.cx, r.cy), sv::isTeamColor(r.color)});
        }
        s.measured.add(*truth, pc.model, f.detections.robots, marker_regions, camera.id,
                       f.detections.rejected_robots);
        if (!f.tracker_reset) s.evaluation.addPrediction(*truth, f.prediction);
      },
      &setup.problems);
  for (const auto& c : setup.cameras)
    s.learned_cells += pipeline.onlineCalibration(c.id)->status().learnedTotal();
  return s;
}

// --- Reporting -----------------------------------------------------------------

double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / v.size();
}

json scoreJson(const sv::RunEvaluation& e) {
  const sv::Score& s = e.total();
  const auto ratio = [](std::int64_t a, std::int64_t b) { return b > 0 ? static_cast<double>(a) / b : 1.0; };
  const std::int64_t excused = s.excused_robots + s.excused_balls;
  return {
      {"robots",
       {{"truth", s.truth_robots},
        {"results", s.result_robots},
        {"matched", s.matched_robots},
        {"false_positives", s.false_robots},
        {"detection_rate", s.robotDetectionRate()},
        {"precision", s.robotPrecision()},
        {"position_rmse_mm", 1e3 * s.robotPositionRmse()},
        {"heading_rmse_deg", s.robotHeadingRmse() * 180 / M_PI}}},
      {"ball",
       {{"truth", s.truth_balls},
        {"results", s.result_balls},
        {"matched", s.matched_balls},
        {"false_positives", s.false_balls},
        {"detection_rate", s.ballDetectionRate()},
        {"precision", s.ballPrecision()},
        {"position_rmse_mm", 1e3 * s.ballPositionRmse()}}},
      {"all",
       {{"detection_rate", ratio(s.matched_robots + s.matched_balls, s.truth_robots + s.truth_balls)},
        {"precision",
         ratio(s.matched_robots + s.matched_balls, s.result_robots + s.result_balls - excused)}}},
      {"identity_switches", e.identitySwitches()},
      {"identity_errors", s.identity_errors},
      {"frames_scored", s.frames},
      {"frames_without_truth", e.unscoredFrames()},
      {"failed_frames", e.failedFrames()},
  };
}

json measuredJson(const sv::MeasuredRate& m) {
  json by_cause = json::object();
  for (const auto& [name, count] : m.rejected_by_cause.named(true)) by_cause[name] = count;
  if (m.no_team_region > 0) by_cause[sv::kNoTeamRegion] = m.no_team_region;
  if (m.team_region_used > 0) by_cause[sv::kTeamRegionUsed] = m.team_region_used;
  return {{"visible", m.visible},
          {"measured", m.measured},
          {"rate", m.rate()},
          {"wrong_id", m.wrong_id},
          {"identification_rejected", m.identification_rejected},
          {"identification_rejected_by_cause", by_cause},
          {"nothing_segmented", m.nothing_segmented}};
}

json stageJson(const RunStats& s) {
  json j;
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"preprocessing", &s.preprocessing},
      {"classification", &s.classification},
      {"recognition_and_pose", &s.recognition},
      {"tracking", &s.tracking},
      {"total", &s.total}};
  for (const auto& [name, v] : stages) {
    j[name] = {{"mean_ms", mean(*v)}, {"p50_ms", sv::percentile(*v, 50)}, {"p99_ms", sv::percentile(*v, 99)}};
  }
  return j;
}

json runSummary(const RunStats& s) {
  const std::int64_t scored = s.evaluation.total().frames;
  const double failure = scored > 0 ? static_cast<double>(s.evaluation.failedFrames()) / scored : 0.0;
  return {{"time_s", s.seconds},
          {"images", s.images},
          {"processed_frames", s.processed},
          {"global_search_frames", s.global},
          {"window_frames", s.windowed},
          {"failed_frames", s.evaluation.failedFrames()},
          {"failure_rate", failure},
          {"success_rate", 1.0 - failure},
          {"frames_per_second", s.seconds > 0 ? s.processed / s.seconds : 0.0},
          {"robot_detection_rate", s.evaluation.total().robotDetectionRate()},
          {"robot_precision", s.evaluation.total().robotPrecision()},
          {"robot_position_rmse_mm", 1e3 * s.evaluation.total().robotPositionRmse()},
          {"prediction_rmse_mm", 1e3 * s.evaluation.predictionRmse()}};
}

// One JSON object per line: the frame to open (stamp, camera), whom it lost and why.
void writeMisses(const std::string& path, const std::vector<sv::MissedRobot>& misses) {
  std::ofstream out(path);
  for (const sv::MissedRobot& m : misses) {
    out << json{{"stamp", m.stamp}, {"camera", m.camera_id}, {"team", sv::teamName(m.team)},
                {"id", m.id},       {"cause", m.cause},      {"rejection", m.rejection},
                {"u", m.pixel.x()}, {"v", m.pixel.y()}}
               .dump()
        << "\n";
  }
  if (!out) throw std::runtime_error(path + ": cannot write the misses");
}

// --- Plots ------------------------------------------------------------------------

void writePlots(const std::string& dir, const sv::RunEvaluation& e, const RunStats* timing,
                const std::vector<std::pair<int, const sv::RunEvaluation*>>& predictions,
                const sv::FieldGeometry& field) {
  ::mkdir(dir.c_str(), 0755);
  const double nan = std::nan("");
  std::vector<sv::TrajectorySeries> trajectories;
  // The first kTrajectorySeconds only: ten robots over minutes are a tangle.
  constexpr double kTrajectorySeconds = 20.0;
  const double start = e.frames().empty() ? 0.0 : e.frames().front().stamp;
  for (const auto& [key, points] : e.trajectories()) {
    sv::TrajectorySeries t;
    t.label = std::string(sv::teamName(key.team)) + " " + std::to_string(key.id);
    t.team = std::string(sv::teamName(key.team));
    for (const sv::TrajectoryPoint& p : points) {
      if (p.t > start + kTrajectorySeconds) break;
      t.t.push_back(p.t);
      t.truth_x.push_back(p.truth_x);
      t.truth_y.push_back(p.truth_y);
      t.tracked_x.push_back(p.result_x.value_or(nan));
      t.tracked_y.push_back(p.result_y.value_or(nan));
    }
    trajectories.push_back(std::move(t));
  }
  sv::plotTrajectories(trajectories, field, dir + "/trajectories.png");

  sv::ErrorSeries errors;
  for (const sv::FrameScore& f : e.frames()) {
    errors.t.push_back(f.stamp - start);
    errors.robot_error_mm.push_back(f.robot_rmse ? 1e3 * *f.robot_rmse : nan);
    errors.ball_error_mm.push_back(f.ball_error ? 1e3 * *f.ball_error : nan);
  }
  sv::plotPositionError(errors, dir + "/position_error.png");

  if (timing) {
    sv::StageTimes stages;
    stages.stage = {"preprocessing", "classification", "recognition and pose", "tracking", "total"};
    stages.ms = {timing->preprocessing, timing->classification, timing->recognition, timing->tracking,
                 timing->total};
    sv::plotStageTimingHistogram(stages, dir + "/stage_times.png");
  }
  if (!predictions.empty()) {
    std::vector<sv::PredictionErrorSeries> series;
    for (const auto& [step, run] : predictions) {
      sv::PredictionErrorSeries p;
      p.frame_step = step;
      const double start = run->predictionErrors().empty() ? 0.0 : run->predictionErrors().front().first;
      for (const auto& [stamp, error] : run->predictionErrors()) {
        p.t.push_back(stamp - start);
        p.error_mm.push_back(1e3 * error);
      }
      series.push_back(std::move(p));
    }
    sv::plotPredictionError(series, dir + "/prediction_error.png");
  }
  std::printf("plots written to %s\n", dir.c_str());
}

void writeJson(const std::string& path, const json& report) {
  std::ofstream out(path);
  out << report.dump(2) << "\n";
  if (!out) throw std::runtime_error(path + ": cannot write the report");
}

// --- Modes --------------------------------------------------------------------

std::vector<sv::FrameRecord> loadTruth(const Options& o, const sv::BagFrames* bag) {
  if (!o.truth.empty()) return sv::readJsonLines(o.truth);
  if (bag) {
    std::vector<sv::FrameRecord> t = bag->groundTruth();
    if (!t.empty()) return t;
    const std::string beside = directoryOf(o.bag) + "/truth.jsonl";
    if (fileExists(beside)) return sv::readJsonLines(beside);
  }
  return {};
}

int resultsOnly(const Options& o) {
  std::unique_ptr<sv::BagFrames> bag;
  if (o.truth.empty()) bag = std::make_unique<sv::BagFrames>(o.bag);
  const sv::TruthTimeline truth(loadTruth(o, bag.get()));
  if (truth.empty())
    throw std::invalid_argument("no ground truth (--truth, or the bag's ground_truth topics)");
  const std::vector<sv::FrameRecord> results = sv::readJsonLines(o.results);
  sv::RunEvaluation e;
  for (const sv::FrameRecord& r : results) {
    if (const sv::FrameRecord* t = truth.at(r.stamp))
      e.add(*t, r);
    else
      e.addUnscored();
  }
  std::printf("evaluate: %s, %zu result frames against %zu ground-truth frames\n", o.results.c_str(),
              results.size(), truth.size());
  json report = scoreJson(e);
  report["results"] = o.results;
  sv::printScore(report);
  if (!o.json.empty()) writeJson(o.json, report);
  if (!o.plots.empty()) writePlots(o.plots, e, nullptr, {}, sv::fieldGeometryByName(o.field));
  return 0;
}

int evaluateBag(const Options& o) {
  const sv::BagFrames bag(o.bag);
  Setup setup;
  setup.bag = &bag;
  setup.patterns = sv::patternSetByName(o.patterns);
  setup.field = sv::fieldGeometryByName(o.field);
  std::vector<const sv::BagCamera*> cameras;
  for (const sv::BagCamera& c : bag.cameras()) {
    if (o.cameras.empty() || std::find(o.cameras.begin(), o.cameras.end(), c.id) != o.cameras.end())
      cameras.push_back(&c);
  }
  for (int id : o.cameras) {
    if (!bag.camera(id)) throw std::invalid_argument(o.bag + ": no camera " + std::to_string(id));
  }
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    sv::PipelineCamera pc;
    pc.id = cameras[i]->id;
    // The first frame (its layout) and the calibration frames, in one pass over the bag.
    const std::map<std::size_t, std::string> samples = samplesByFrame(o, i, pc.id);
    const std::map<std::size_t, std::string> more = moreSamples(o, pc.id);
    std::set<std::size_t> wanted{0};
    if (o.calibration_images.empty()) {
      for (const auto& entry : samples) wanted.insert(entry.first);
    }
    for (const auto& entry : more) wanted.insert(entry.first);
    const std::map<std::size_t, sv::BagFrames::Image> frames = bag.images(pc.id, wanted);
    if (!frames.count(0)) {
      throw std::invalid_argument(o.bag + ": camera " + std::to_string(pc.id) +
                                  "'s first image cannot be read");
    }
    pc.layout = frames.at(0).layout;
    pc.model = cameraModel(o, *cameras[i], i, frames.at(0), setup.field);
    pc.segmentation = colorModel(o, setup.patterns, samples, more, frames, i, pc.id);
    setup.cameras.push_back(std::move(pc));
  }
  const sv::TruthTimeline truth(loadTruth(o, &bag));
  setup.truth = truth.empty() ? nullptr : &truth;

  sv::VisionPipelineParams params;
  params.frame_step = o.frame_step;
  params.search.windows.side_px = o.window_side;
  params.search.search_windows = o.windows;
  params.segmentation.ball_streaks = o.ball_streaks;
  params.online_calibration.enabled = o.online_calibration;
  for (std::size_t i = 0; i < o.measurement_offsets.size(); ++i) {
    if (o.measurement_offsets.size() == 1)
      params.tracker.measurement_offset = o.measurement_offsets[i];
    else if (i < setup.cameras.size())
      params.tracker.camera_measurement_offsets[setup.cameras[i].id] = o.measurement_offsets[i];
    else
      throw std::invalid_argument("--measurement-offset has more entries than there are cameras");
  }

  std::unique_ptr<sv::JsonLinesWriter> results;
  if (!o.results.empty()) results = std::make_unique<sv::JsonLinesWriter>(o.results);
  std::ofstream trace;
  if (!o.trace.empty()) {
    trace.open(o.trace);
    if (!trace) throw std::runtime_error(o.trace + ": cannot write the trace");
  }
  const RunStats main = run(setup, params, results.get(), o.trace.empty() ? nullptr : &trace);
  if (!o.trace.empty() && !trace.flush()) throw std::runtime_error(o.trace + ": cannot write the trace");
  if (main.processed == 0) throw std::invalid_argument(o.bag + ": no frame could be processed");

  std::printf(
      "evaluate: %s, %zu camera(s), %lld images, %lld processed (frame_step %d, %s), pattern %s, %s\n",
      o.bag.c_str(), setup.cameras.size(), static_cast<long long>(main.images),
      static_cast<long long>(main.processed), o.frame_step,
      o.windows ? ("windows R = " + std::to_string(o.window_side) + " px").c_str() : "no windows",
      setup.patterns.name.c_str(), setup.truth ? "ground truth found" : "NO ground truth");
  const sv::BagImageProblems& skipped = setup.problems;
  if (skipped.unsupported_encoding + skipped.truncated + skipped.other_format > 0) {
    std::printf(
        "skipped: %zu images of unsupported encodings, %zu truncated, %zu of another size or encoding than "
        "the camera's first\n",
        skipped.unsupported_encoding, skipped.truncated, skipped.other_format);
  }
  json report = scoreJson(main.evaluation);
  if (setup.truth) {
    report["measured"] = measuredJson(main.measured.total());
    json by_robot = json::array();
    for (const auto& [key, m] : main.measured.byRobot()) {
      json row = measuredJson(m);
      row["team"] = sv::teamName(key.first);
      row["id"] = key.second;
      by_robot.push_back(row);
    }
    report["measured"]["by_robot"] = by_robot;
  }
  report["bag"] = o.bag;
  report["frame_step"] = o.frame_step;
  report["window_side"] = o.window_side;
  report["search_windows"] = o.windows;
  report["ball_streaks"] = o.ball_streaks;
  report["online_calibration"] = o.online_calibration;
  if (o.online_calibration) report["learned_cells"] = main.learned_cells;
  report["frames_processed"] = main.processed;
  report["global_search_frames"] = main.global;
  report["window_frames"] = main.windowed;
  report["frames_per_second"] = main.processed / main.seconds;
  report["images"] = main.images;
  report["cameras"] = setup.cameras.size();
  report["width"] = setup.cameras.front().model.width();
  report["height"] = setup.cameras.front().model.height();
  report["encoding"] = sv::encodingForPixelLayout(setup.cameras.front().layout);
  report["pattern"] = setup.patterns.name;
  report["stages"] = stageJson(main);
  if (setup.truth) sv::printScore(report);
  std::printf(
      "speed:  %.0f frames/s in-process (%.3f ms mean, p50 %.3f, p99 %.3f ms per frame), %lld global-search "
      "frames, %lld in windows\n",
      main.processed / main.seconds, mean(main.total), sv::percentile(main.total, 50),
      sv::percentile(main.total, 99), static_cast<long long>(main.global),
      static_cast<long long>(main.windowed));

  if (o.table2) {
    sv::VisionPipelineParams whole = params;
    whole.search.search_windows = !o.windows;
    const RunStats other = run(setup, whole, nullptr);
    const json with = o.windows ? stageJson(main) : stageJson(other);
    const json without = o.windows ? stageJson(other) : stageJson(main);
    report["table2"] = {{"with_windows", with}, {"without_windows", without}};
    sv::printTable2(with, without);
  }

  std::vector<std::unique_ptr<RunStats>> sweep_runs;
  std::vector<std::pair<int, const sv::RunEvaluation*>> predictions;
  if (o.sweep) {
    json rows = json::array();
    for (int step : {1, 2, 3, 4}) {
      for (int side : {50, 100, 200, 400}) {
        sv::VisionPipelineParams p = params;
        p.frame_step = step;
        p.search.windows.side_px = side;
        p.search.search_windows = true;
        sweep_runs.push_back(std::make_unique<RunStats>(run(setup, p, nullptr)));
        json row = runSummary(*sweep_runs.back());
        row["frame_step"] = step;
        row["window_side"] = side;
        rows.push_back(row);
        if (side == o.window_side) predictions.emplace_back(step, &sweep_runs.back()->evaluation);
      }
    }
    report["table1"] = rows;
    sv::printTable1(rows);
  }
  if (!o.plots.empty() && setup.truth) {
    if (predictions.empty()) {
      for (int step : {1, 2, 3, 4}) {
        sv::VisionPipelineParams p = params;
        p.frame_step = step;
        sweep_runs.push_back(std::make_unique<RunStats>(run(setup, p, nullptr)));
        predictions.emplace_back(step, &sweep_runs.back()->evaluation);
      }
    }
    writePlots(o.plots, main.evaluation, &main, predictions, setup.field);
  }
  if (!o.json.empty()) writeJson(o.json, report);
  if (!o.misses.empty()) writeMisses(o.misses, main.measured.misses());
  if (!o.markdown.empty()) {
    std::ofstream md(o.markdown);
    md << sv::markdownReport(report, o.title.empty() ? o.bag : o.title);
    if (!md) throw std::runtime_error(o.markdown + ": cannot write the Markdown report");
  }
  if (results) std::printf("results: %zu frames written to %s\n", results->written(), o.results.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "evaluate: runs the vision pipeline on a recording and scores it against the ground truth\n"
      "(or scores a results file with --results-only); docs/tools.md, docs/evaluation.md",
      "evaluate"};
  addOptions(app, o);
  if (const auto status = sv::parseCommandLine(app, argc, argv)) return *status;
  if (const std::string problem = combinationProblem(o); !problem.empty())
    return sv::usageError(app, problem);
  try {
    return o.results_only ? resultsOnly(o) : evaluateBag(o);
  } catch (const std::exception& e) {
    std::cerr << "evaluate: " << e.what() << "\n";
    return 2;
  }
}
