// Camera calibration from the painted field lines of one image: the camera model (pose,
// and with estimate_intrinsics the focal length and radial distortion k1, k2; the principal
// point optionally) that minimises the distance of the image's line pixels
// (field_line_pixels.h) to the field's lines and arcs (FieldGeometry) projected through it.
//
// Iterated closest points: every line pixel is taken back to the field plane through the
// current model and paired with its nearest marking (pixels near two markings, e.g. at
// corners, and pixels far from all of them, e.g. on robots, are left out); then
// Levenberg-Marquardt minimises the distance in the image across the projected marking
// (raw pixels, through CameraModel::project: the distortion model the pipeline uses). The
// pairing gate shrinks from coarse to fine as the model improves.
//
// The start: a model from >= 4 approximate correspondences (initialModelFromPoints: the
// pose and, with estimate_intrinsics, k1 fitted to them) or any guess.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "soccer_vision/calibration/field_line_pixels.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/field_geometry.h"

namespace soccer_vision {

struct FieldLineFitParams {
  bool estimate_intrinsics = false;  // focal length (fx = fy ratio kept), k1, k2
  // With estimate_intrinsics: false keeps the focal length given (k1, k2 only). A camera
  // looking almost straight down cannot tell its focal length from its height: 0.5 % of f
  // is 20 mm of height at 4 m and 3° of tilt (robot positions stay within 1 mm).
  bool estimate_focal_length = true;
  bool estimate_principal_point = false;  // cx, cy as well (needs a tilted camera to be observable)
  // Pairing gates [m on the field], one stage of fitting each, coarse to fine.
  std::vector<double> gates{0.25, 0.12, 0.06, 0.03, 0.03};
  double ambiguity = 0.04;  // m: pixels whose second-nearest marking is this close too are left out
  int iterations_per_stage = 15;
  double huber_px = 1.0;  // robust loss: residuals beyond this count linearly
};

struct FieldLineFit {
  CameraModel camera;
  double rms_px = 0;      // across-line residual of the paired line pixels (within 3 px) at the end
  int pixels_paired = 0;  // line pixels paired with a marking at the last stage
  int pixels_total = 0;   // line pixels found
  int pixels_within_3px = 0;
  double coverage = 0;  // share of the markings' length in the image with line pixels near
};

// The fit; throws std::invalid_argument when fewer than 50 line pixels can be paired
// (no field lines in the image, or a starting model far off).
FieldLineFit fitCameraToFieldLines(const std::vector<FieldLinePixel>& pixels, const FieldGeometry& field,
                                   const CameraModel& start, const FieldLineFitParams& params = {});

// A start from >= 4 approximate correspondences (e.g. clicked corners): the pose by
// solveCameraPose and, with estimate_k1, the pose and k1 refitted to the points.
CameraModel initialModelFromPoints(const CameraIntrinsics& intrinsics,
                                   const std::vector<FieldCorrespondence>& points, bool estimate_k1);

// The corners of the field's rectangles a camera may see whole (the playing area, each
// half) matched to 4 clicked pixels in any order: every rectangle and every assignment of
// the clicks to its corners that keeps their cyclic order, each started from
// initialModelFromPoints and scored by the line pixels near the projected markings; the
// best start. Throws std::invalid_argument when the clicks are not 4 or no assignment fits.
CameraModel initialModelFromCorners(const CameraIntrinsics& intrinsics,
                                    const std::vector<Eigen::Vector2d>& clicks, const FieldGeometry& field,
                                    const std::vector<FieldLinePixel>& pixels, bool estimate_k1);

// What to do next after a fit, for the user: empty when the fit looks right, else a
// sentence naming the symptom and the remedy (e.g. "RMS 2.8 px: intrinsics likely off;
// try --estimate-intrinsics").
std::string fieldLineFitAdvice(const FieldLineFit& fit, bool intrinsics_estimated, double max_rms_px);

// A pose from clicked points refined on the field lines of one image, the intrinsics kept:
// what evaluate and the calibration UI do after the clicks (calibrate_field --image --points
// with its own checks). `fit` when the lines confirm it (across-line RMS <= max_rms_px);
// else `reason` says why the clicked pose stays. `advice`: fieldLineFitAdvice's warning for
// an accepted fit, if any. `bgr`: CV_8UC3, the image the lines are detected on.
struct LineRefinement {
  std::optional<FieldLineFit> fit;
  std::string reason, advice;
};
LineRefinement refinePoseOnFieldLines(const cv::Mat& bgr, const FieldGeometry& field,
                                      const CameraModel& start, double max_rms_px = 1.0);

}  // namespace soccer_vision
