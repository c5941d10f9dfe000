#include "soccer_vision/calibration/camera_pose_solver.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>

namespace soccer_vision {
namespace {

bool finite(const FieldCorrespondence& c) { return c.pixel.allFinite() && c.field.allFinite(); }

// Singular values of a centred point cloud: [0] largest spread, [1] second (0 for points
// on a line), [2] out-of-plane (0 for coplanar points); as RMS distances.
template <int N>
Eigen::Matrix<double, N, 1> spread(const std::vector<Eigen::Matrix<double, N, 1>>& pts) {
  Eigen::Matrix<double, N, 1> mean = Eigen::Matrix<double, N, 1>::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix<double, Eigen::Dynamic, N> a(pts.size(), N);
  for (std::size_t i = 0; i < pts.size(); ++i) a.row(i) = (pts[i] - mean).transpose();
  return Eigen::JacobiSVD<Eigen::Matrix<double, Eigen::Dynamic, N>>(a).singularValues() /
         std::sqrt(static_cast<double>(pts.size()));
}

Eigen::Matrix3d rodrigues(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

// Pose as camera_T_field (what projection applies): p_cam = R p_field + t.
struct WorldToCamera {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Isometry3d fieldTCamera() const {
    Eigen::Isometry3d cTf = Eigen::Isometry3d::Identity();
    cTf.linear() = R;
    cTf.translation() = t;
    return cTf.inverse();
  }
};

// Residuals (2 per point) of raw-pixel reprojection; a point behind the camera gets a
// large residual so that LM is pushed back towards valid poses.
Eigen::VectorXd residuals(const CameraIntrinsics& k, const WorldToCamera& pose,
                          const std::vector<FieldCorrespondence>& pts) {
  const CameraModel cam(k, pose.fieldTCamera());
  Eigen::VectorXd r(2 * pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto px = cam.project(pts[i].field);
    if (px) {
      r.segment<2>(2 * i) = *px - pts[i].pixel;
    } else {
      r.segment<2>(2 * i).setConstant(1e6);
    }
  }
  return r;
}

// Levenberg-Marquardt over a left-multiplied rotation increment and the translation,
// numerical Jacobian (central differences; the cost is cheap and the point count small).
WorldToCamera refine(const CameraIntrinsics& k, WorldToCamera pose,
                     const std::vector<FieldCorrespondence>& pts, const CameraPoseSolverParams& params,
                     int& iterations) {
  auto apply = [](const WorldToCamera& p, const Eigen::Matrix<double, 6, 1>& d) {
    WorldToCamera q;
    q.R = rodrigues(d.head<3>()) * p.R;
    q.t = rodrigues(d.head<3>()) * p.t + d.tail<3>();
    return q;
  };
  Eigen::VectorXd r = residuals(k, pose, pts);
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  iterations = 0;
  for (int it = 0; it < params.max_iterations; ++it) {
    ++iterations;
    Eigen::MatrixXd J(r.size(), 6);
    for (int j = 0; j < 6; ++j) {
      const double h = j < 3 ? 1e-7 : 1e-7 * std::max(1.0, pose.t.norm());
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      d[j] = h;
      const Eigen::VectorXd rp = residuals(k, apply(pose, d), pts);
      d[j] = -h;
      const Eigen::VectorXd rm = residuals(k, apply(pose, d), pts);
      J.col(j) = (rp - rm) / (2 * h);
    }
    const Eigen::Matrix<double, 6, 6> JtJ = J.transpose() * J;
    const Eigen::Matrix<double, 6, 1> g = J.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 20 && !improved; ++tries) {
      Eigen::Matrix<double, 6, 6> A = JtJ;
      A.diagonal() += lambda * JtJ.diagonal().cwiseMax(1e-12);
      const Eigen::Matrix<double, 6, 1> step = A.ldlt().solve(-g);
      const WorldToCamera candidate = apply(pose, step);
      const Eigen::VectorXd rc = residuals(k, candidate, pts);
      const double c = rc.squaredNorm();
      if (c < cost) {
        const double decrease = (cost - c) / std::max(cost, 1e-300);
        pose = candidate;
        r = rc;
        cost = c;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        if (decrease < params.convergence) return pose;
      } else {
        lambda *= 10;
      }
    }
    if (!improved || cost < 1e-24) break;
  }
  return pose;
}

}  // namespace

std::vector<double> reprojectionErrors(const CameraModel& camera,
                                       const std::vector<FieldCorrespondence>& points) {
  std::vector<double> e;
  e.reserve(points.size());
  for (const auto& p : points) {
    const auto px = camera.project(p.field);
    e.push_back(px ? (*px - p.pixel).norm() : std::numeric_limits<double>::infinity());
  }
  return e;
}

CameraPoseSolution solveCameraPose(const CameraIntrinsics& k, const std::vector<FieldCorrespondence>& pts,
                                   const CameraPoseSolverParams& params) {
  if (pts.size() < 4) {
    throw std::invalid_argument("camera pose: need at least 4 correspondences, got " +
                                std::to_string(pts.size()));
  }
  if (!(k.fx > 0 && k.fy > 0) || !std::isfinite(k.cx) || !std::isfinite(k.cy)) {
    throw std::invalid_argument("camera pose: intrinsics have no valid focal length / principal point");
  }
  for (double d : k.dist) {
    if (!std::isfinite(d)) throw std::invalid_argument("camera pose: non-finite distortion coefficient");
  }
  std::vector<Eigen::Vector3d> field;
  std::vector<Eigen::Vector2d> pixels;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!finite(pts[i])) {
      throw std::invalid_argument("camera pose: correspondence " + std::to_string(i) +
                                  " has a non-finite value");
    }
    field.push_back(pts[i].field);
    pixels.push_back(pts[i].pixel);
  }
  // A point given twice adds no constraint: 4 points of which 3 are distinct once passed.
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (std::size_t j = i + 1; j < pts.size(); ++j) {
      const bool same_field = (field[i] - field[j]).norm() < 1e-6;
      const bool same_pixel = (pixels[i] - pixels[j]).norm() < 1e-6;
      if (same_field || same_pixel) {
        throw std::invalid_argument("camera pose: correspondences " + std::to_string(i) + " and " +
                                    std::to_string(j) + " have the same " +
                                    (same_field ? "field point" : "pixel") + ": the points must be distinct");
      }
    }
  }
  const Eigen::Vector3d s3 = spread<3>(field);
  if (s3[1] < params.min_spread) {
    throw std::invalid_argument(
        "camera pose: the field points are (nearly) collinear or coincide (spread across "
        "their line " +
        std::to_string(s3[1]) + " m)");
  }
  const Eigen::Vector2d s2 = spread<2>(pixels);
  if (s2[1] < params.min_pixel_spread) {
    throw std::invalid_argument("camera pose: the pixels are (nearly) collinear (spread " +
                                std::to_string(s2[1]) + " px): the camera lies in the plane of the points");
  }
  const bool coplanar = s3[2] < 1e-6 * std::max(1.0, s3[0]);

  // Initial poses in normalised undistorted coordinates (K = I, no distortion).
  const CameraModel lens(k, Eigen::Isometry3d::Identity());
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    object.emplace_back(field[i].x(), field[i].y(), field[i].z());
    const Eigen::Vector2d n =
        lens.undistortNormalized({(pixels[i].x() - k.cx) / k.fx, (pixels[i].y() - k.cy) / k.fy});
    image.emplace_back(n.x(), n.y());
  }
  std::vector<cv::Mat> rvecs, tvecs;
  const cv::Mat eye = cv::Mat::eye(3, 3, CV_64F);
  try {
    if (coplanar) {
      cv::solvePnPGeneric(object, image, eye, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
    }
    if (rvecs.empty()) {
      cv::solvePnPGeneric(object, image, eye, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_SQPNP);
    }
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(std::string("camera pose: no initial pose (OpenCV: ") + e.err + ")");
  }

  CameraPoseSolution best;
  best.intrinsics = k;
  double best_cost = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < rvecs.size(); ++c) {
    cv::Mat R;
    cv::Rodrigues(rvecs[c], R);
    WorldToCamera pose;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) pose.R(i, j) = R.at<double>(i, j);
      pose.t[i] = tvecs[c].at<double>(i);
    }
    int iterations = 0;
    pose = refine(k, pose, pts, params, iterations);
    const double cost = residuals(k, pose, pts).squaredNorm();
    if (cost < best_cost) {
      best_cost = cost;
      best.field_T_camera = pose.fieldTCamera();
      best.iterations = iterations;
    }
  }
  if (!std::isfinite(best_cost)) throw std::invalid_argument("camera pose: OpenCV found no initial pose");
  best.errors_px = reprojectionErrors(best.model(), pts);
  double sum = 0;
  for (double e : best.errors_px) {
    if (!std::isfinite(e)) {
      throw std::invalid_argument("camera pose: no pose puts every field point in front of the camera");
    }
    sum += e * e;
    best.max_px = std::max(best.max_px, e);
  }
  best.rms_px = std::sqrt(sum / static_cast<double>(best.errors_px.size()));
  return best;
}

}  // namespace soccer_vision
