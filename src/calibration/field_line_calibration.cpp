#include "soccer_vision/calibration/field_line_calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/calibration/camera_pose_solver.h"
#include "soccer_vision/common/field_markings_image.h"

namespace soccer_vision {
namespace {

// Parameters of a camera model relative to a base model: rotation vector (applied in the
// optical frame), translation offset [m], log focal scale, k1, k2 offsets, principal point
// offset [px]. Only the active ones are varied.
enum Param { Rx, Ry, Rz, Tx, Ty, Tz, LogF, K1, K2, Cx, Cy, kNumParams };

struct ModelParams {
  const CameraModel& base;
  std::vector<int> active;

  CameraModel model(const Eigen::VectorXd& p) const {
    double v[kNumParams] = {};
    for (std::size_t i = 0; i < active.size(); ++i) v[active[i]] = p[static_cast<Eigen::Index>(i)];
    CameraIntrinsics k = base.intrinsics();
    const double scale = std::exp(v[LogF]);
    k.fx *= scale;
    k.fy *= scale;
    k.dist[0] += v[K1];
    k.dist[1] += v[K2];
    k.cx += v[Cx];
    k.cy += v[Cy];
    Eigen::Isometry3d pose = base.fieldTCamera();
    const Eigen::Vector3d w(v[Rx], v[Ry], v[Rz]);
    if (w.norm() > 0)
      pose.linear() = pose.linear() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    pose.translation() += Eigen::Vector3d(v[Tx], v[Ty], v[Tz]);
    return CameraModel(k, pose);
  }
  // Finite-difference steps.
  Eigen::VectorXd steps() const {
    static const double step[kNumParams] = {1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-7, 1e-6, 1e-6, 1e-4, 1e-4};
    Eigen::VectorXd s(active.size());
    for (std::size_t i = 0; i < active.size(); ++i) s[static_cast<Eigen::Index>(i)] = step[active[i]];
    return s;
  }
};

using Residuals = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// Levenberg-Marquardt with Huber weights (re-weighted every iteration); forward-difference
// Jacobian. Returns the parameters.
Eigen::VectorXd levenbergMarquardt(const Residuals& f, Eigen::VectorXd p, const Eigen::VectorXd& steps,
                                   int iterations, double huber) {
  auto weights = [&](const Eigen::VectorXd& r) {
    Eigen::VectorXd w(r.size());
    for (Eigen::Index i = 0; i < r.size(); ++i) w[i] = std::abs(r[i]) <= huber ? 1.0 : huber / std::abs(r[i]);
    return w;
  };
  auto cost = [&](const Eigen::VectorXd& r) {
    double c = 0;
    for (Eigen::Index i = 0; i < r.size(); ++i) {
      const double a = std::abs(r[i]);
      c += a <= huber ? 0.5 * a * a : huber * (a - 0.5 * huber);
    }
    return c;
  };
  Eigen::VectorXd r = f(p);
  double c = cost(r);
  double lambda = 1e-3;
  for (int it = 0; it < iterations; ++it) {
    Eigen::MatrixXd J(r.size(), p.size());
    for (Eigen::Index j = 0; j < p.size(); ++j) {
      Eigen::VectorXd q = p;
      q[j] += steps[j];
      J.col(j) = (f(q) - r) / steps[j];
    }
    const Eigen::VectorXd w = weights(r);
    const Eigen::MatrixXd JtW = J.transpose() * w.asDiagonal();
    const Eigen::MatrixXd A = JtW * J;
    const Eigen::VectorXd g = JtW * r;
    bool improved = false;
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::MatrixXd B = A;
      for (Eigen::Index j = 0; j < B.rows(); ++j) B(j, j) += lambda * std::max(A(j, j), 1e-12);
      const Eigen::VectorXd delta = B.ldlt().solve(-g);
      if (!delta.allFinite()) break;
      const Eigen::VectorXd q = p + delta;
      const Eigen::VectorXd rq = f(q);
      const double cq = cost(rq);
      if (cq < c) {
        const double gain = (c - cq) / std::max(c, 1e-300);
        p = q;
        r = rq;
        c = cq;
        lambda = std::max(lambda / 3, 1e-9);
        improved = true;
        if (gain < 1e-10) return p;
      } else {
        lambda *= 4;
      }
    }
    if (!improved) break;
  }
  return p;
}

// A painted marking's closest point to q on the field, its tangent and distance.
struct Closest {
  Eigen::Vector2d point = Eigen::Vector2d::Zero(), tangent = Eigen::Vector2d::UnitX();
  double distance = std::numeric_limits<double>::infinity();
};

Closest closestOnSegment(const LineSegment& s, const Eigen::Vector2d& q) {
  const Eigen::Vector2d d = s.b - s.a;
  const double t = std::clamp((q - s.a).dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
  Closest c;
  c.point = s.a + t * d;
  c.tangent = d.normalized();
  c.distance = (q - c.point).norm();
  return c;
}

Closest closestOnArc(const CircleArc& a, const Eigen::Vector2d& q) {
  const Eigen::Vector2d v = q - a.centre;
  double phi = std::atan2(v.y(), v.x());
  Closest c;
  if (!a.fullCircle()) {
    while (phi < a.a1) phi += 2 * M_PI;
    while (phi >= a.a1 + 2 * M_PI) phi -= 2 * M_PI;
    if (phi > a.a2) {  // beyond the arc: its nearer end
      const double to_end = phi - a.a2, to_start = a.a1 + 2 * M_PI - phi;
      phi = to_end < to_start ? a.a2 : a.a1;
    }
  }
  c.point = a.centre + a.radius * Eigen::Vector2d(std::cos(phi), std::sin(phi));
  c.tangent = Eigen::Vector2d(-std::sin(phi), std::cos(phi));
  c.distance = (q - c.point).norm();
  return c;
}

struct Markings {
  std::vector<LineSegment> lines;
  std::vector<CircleArc> arcs;
  explicit Markings(const FieldGeometry& field) : lines(field.lines()), arcs(field.circles()) {}

  // Nearest marking and the distance to the second nearest.
  std::pair<Closest, double> nearest(const Eigen::Vector2d& q) const {
    Closest best;
    double second = std::numeric_limits<double>::infinity();
    auto consider = [&](const Closest& c) {
      if (c.distance < best.distance) {
        second = best.distance;
        best = c;
      } else {
        second = std::min(second, c.distance);
      }
    };
    for (const LineSegment& l : lines) consider(closestOnSegment(l, q));
    for (const CircleArc& a : arcs) consider(closestOnArc(a, q));
    return {best, second};
  }
};

struct Pair {
  Eigen::Vector2d pixel;
  Eigen::Vector3d point;    // on the marking, z = 0
  Eigen::Vector3d tangent;  // along it
};

std::vector<Pair> pairPixels(const std::vector<FieldLinePixel>& pixels, const Markings& markings,
                             const CameraModel& camera, double gate, double ambiguity) {
  std::vector<Pair> out;
  for (const FieldLinePixel& p : pixels) {
    const auto q = camera.pixelToField(p.pixel, 0.0);
    if (!q || !q->allFinite()) continue;
    const auto [c, second] = markings.nearest(q->head<2>());
    if (c.distance > gate || second < c.distance + ambiguity) continue;
    out.push_back({p.pixel, {c.point.x(), c.point.y(), 0.0}, {c.tangent.x(), c.tangent.y(), 0.0}});
  }
  return out;
}

// Distance of each pixel across its marking's projection (signed, raw pixels).
Eigen::VectorXd acrossLine(const CameraModel& camera, const std::vector<Pair>& pairs) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(pairs.size()));
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const auto a = camera.project(pairs[i].point);
    const auto b = camera.project(pairs[i].point + 0.01 * pairs[i].tangent);
    if (!a || !b || (*b - *a).norm() < 1e-9) {
      r[static_cast<Eigen::Index>(i)] = 50.0;  // behind the camera: a large, flat penalty
      continue;
    }
    const Eigen::Vector2d d = (*b - *a).normalized();
    r[static_cast<Eigen::Index>(i)] = Eigen::Vector2d(-d.y(), d.x()).dot(pairs[i].pixel - *a);
  }
  return r;
}

std::vector<int> activeParams(bool intrinsics, bool focal_length, bool principal_point) {
  std::vector<int> a{Rx, Ry, Rz, Tx, Ty, Tz};
  if (intrinsics && focal_length) a.push_back(LogF);
  if (intrinsics) a.insert(a.end(), {K1, K2});
  if (principal_point) a.insert(a.end(), {Cx, Cy});
  return a;
}

// Share of line pixels within `gate` metres of a marking through this camera.
double lineScore(const CameraModel& camera, const std::vector<FieldLinePixel>& pixels,
                 const Markings& markings, double gate) {
  if (pixels.empty()) return 0;
  int near = 0;
  const std::size_t step = std::max<std::size_t>(1, pixels.size() / 1500);
  int n = 0;
  for (std::size_t i = 0; i < pixels.size(); i += step, ++n) {
    const auto q = camera.pixelToField(pixels[i].pixel, 0.0);
    if (q && q->allFinite() && markings.nearest(q->head<2>()).first.distance <= gate) ++near;
  }
  return static_cast<double>(near) / std::max(n, 1);
}

}  // namespace

FieldLineFit fitCameraToFieldLines(const std::vector<FieldLinePixel>& pixels, const FieldGeometry& field,
                                   const CameraModel& start, const FieldLineFitParams& params) {
  const Markings markings(field);
  CameraModel camera = start;
  std::vector<Pair> pairs;
  for (double gate : params.gates) {
    pairs = pairPixels(pixels, markings, camera, gate, params.ambiguity);
    if (pairs.size() < 50) {
      throw std::invalid_argument(
          "only " + std::to_string(pairs.size()) + " of " + std::to_string(pixels.size()) +
          " line pixels lie near the field model's lines (gate " + std::to_string(gate) +
          " m): no field lines in the image, the wrong field, or a start far off");
    }
    const ModelParams model{camera, activeParams(params.estimate_intrinsics, params.estimate_focal_length,
                                                 params.estimate_principal_point)};
    const Eigen::VectorXd p =
        levenbergMarquardt([&](const Eigen::VectorXd& q) { return acrossLine(model.model(q), pairs); },
                           Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.active.size())),
                           model.steps(), params.iterations_per_stage, params.huber_px);
    camera = model.model(p);
  }
  FieldLineFit fit;
  fit.camera = camera;
  fit.pixels_total = static_cast<int>(pixels.size());
  fit.pixels_paired = static_cast<int>(pairs.size());
  const Eigen::VectorXd r = acrossLine(camera, pairs);
  double sum = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    if (std::abs(r[i]) > 3.0) continue;
    sum += r[i] * r[i];
    ++fit.pixels_within_3px;
  }
  fit.rms_px = fit.pixels_within_3px ? std::sqrt(sum / fit.pixels_within_3px) : 0.0;
  // Coverage: points along the projected markings with a line pixel within 3 px.
  const CameraIntrinsics& k = camera.intrinsics();
  cv::Mat found = cv::Mat::zeros(k.height, k.width, CV_8U);
  for (const FieldLinePixel& p : pixels) {
    const cv::Point c(cvRound(p.pixel.x()), cvRound(p.pixel.y()));
    cv::circle(found, c, 3, cv::Scalar(255), cv::FILLED);
  }
  int samples = 0, covered = 0;
  for (const auto& line : projectFieldMarkings(camera, field, 0.05, 5.0)) {
    for (const Eigen::Vector2d& p : line) {
      ++samples;
      covered += found.at<std::uint8_t>(cvRound(p.y()), cvRound(p.x())) != 0;
    }
  }
  fit.coverage = samples ? static_cast<double>(covered) / samples : 0.0;
  return fit;
}

CameraModel initialModelFromPoints(const CameraIntrinsics& intrinsics,
                                   const std::vector<FieldCorrespondence>& points, bool estimate_k1) {
  const CameraPoseSolution solution = solveCameraPose(intrinsics, points);
  if (!estimate_k1) return solution.model();
  // Pose and k1 to the points; k1 held near its start by a prior (a k1 change of 0.3 costs
  // as much as 5 px), since 4 clicked points barely determine it.
  const CameraModel base = solution.model();
  const ModelParams model{base, {Rx, Ry, Rz, Tx, Ty, Tz, K1}};
  const Residuals f = [&](const Eigen::VectorXd& q) {
    const CameraModel m = model.model(q);
    Eigen::VectorXd r(static_cast<Eigen::Index>(2 * points.size() + 1));
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto px = m.project(points[i].field);
      const Eigen::Vector2d e = px ? Eigen::Vector2d(*px - points[i].pixel) : Eigen::Vector2d(1e3, 1e3);
      r.segment<2>(static_cast<Eigen::Index>(2 * i)) = e;
    }
    r[r.size() - 1] = 5.0 * q[6] / 0.3;
    return r;
  };
  const Eigen::VectorXd p = levenbergMarquardt(f, Eigen::VectorXd::Zero(7), model.steps(), 50,
                                               std::numeric_limits<double>::infinity());
  return model.model(p);
}

CameraModel initialModelFromCorners(const CameraIntrinsics& intrinsics,
                                    const std::vector<Eigen::Vector2d>& clicks, const FieldGeometry& field,
                                    const std::vector<FieldLinePixel>& pixels, bool estimate_k1) {
  if (clicks.size() != 4) throw std::invalid_argument("--corners needs 4 pixels (u,v pairs)");
  // The clicks in cyclic order around their centroid.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& c : clicks) centroid += c / 4.0;
  std::vector<Eigen::Vector2d> ordered = clicks;
  std::sort(ordered.begin(), ordered.end(), [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return std::atan2(a.y() - centroid.y(), a.x() - centroid.x()) <
           std::atan2(b.y() - centroid.y(), b.x() - centroid.x());
  });
  const double hl = field.halfLength(), hw = field.halfWidth();
  const std::vector<std::array<Eigen::Vector2d, 4>> rectangles = {
      {{{-hl, -hw}, {hl, -hw}, {hl, hw}, {-hl, hw}}},  // the playing area
      {{{-hl, -hw}, {0, -hw}, {0, hw}, {-hl, hw}}},    // the half at negative x
      {{{0, -hw}, {hl, -hw}, {hl, hw}, {0, hw}}},      // the half at positive x
  };
  const Markings markings(field);
  std::optional<CameraModel> best;
  double best_score = -1;
  for (const auto& rect : rectangles) {
    for (int rotation = 0; rotation < 4; ++rotation) {
      for (int direction : {1, -1}) {
        std::vector<FieldCorrespondence> points;
        for (int i = 0; i < 4; ++i) {
          const Eigen::Vector2d& corner =
              rect[static_cast<std::size_t>(((rotation + direction * i) % 4 + 4) % 4)];
          points.push_back({ordered[static_cast<std::size_t>(i)], {corner.x(), corner.y(), 0.0}});
        }
        try {
          const CameraModel m = initialModelFromPoints(intrinsics, points, estimate_k1);
          const auto errors = reprojectionErrors(m, points);
          const double worst = *std::max_element(errors.begin(), errors.end());
          if (!(worst < 30.0) || m.cameraCentre().z() < 0.5) continue;
          // Ties (the field's 180° symmetry) keep the first: the camera over negative x.
          const double score = lineScore(m, pixels, markings, 0.1);
          if (score > best_score + 0.02) {
            best_score = score;
            best = m;
          }
        } catch (const std::invalid_argument&) {
          continue;
        }
      }
    }
  }
  if (!best) {
    throw std::invalid_argument(
        "the 4 corners fit no rectangle of the field (the playing area or a half) within 30 px: click the "
        "corners of the area the camera sees, or give --points");
  }
  return *best;
}

std::string fieldLineFitAdvice(const FieldLineFit& fit, bool intrinsics_estimated, double max_rms_px) {
  char buf[400];
  if (fit.rms_px > max_rms_px) {
    if (!intrinsics_estimated) {
      std::snprintf(buf, sizeof buf, "RMS %.2f px: intrinsics likely off; try --estimate-intrinsics",
                    fit.rms_px);
    } else {
      std::snprintf(buf, sizeof buf,
                    "RMS %.2f px even with the intrinsics estimated: the start is likely far off (check the "
                    "corners: the 4 corners of the playing area or of the half the camera sees) or the lines "
                    "are hard to see (light, focus); try --points with more landmarks",
                    fit.rms_px);
    }
    return buf;
  }
  const double inliers =
      fit.pixels_paired ? static_cast<double>(fit.pixels_within_3px) / fit.pixels_paired : 0;
  if (inliers < 0.6) {
    std::snprintf(
        buf, sizeof buf,
        "only %.0f %% of the paired line pixels lie within 3 px of the field model: wrong --field, or "
        "the start converged to the wrong lines; check the corners",
        100 * inliers);
    return buf;
  }
  if (fit.coverage < 0.5) {
    std::snprintf(
        buf, sizeof buf,
        "line pixels found along only %.0f %% of the projected field lines: the model may be off where "
        "the image shows no lines; check the overlay (detect --overlay)",
        100 * fit.coverage);
    return buf;
  }
  return "";
}

LineRefinement refinePoseOnFieldLines(const cv::Mat& bgr, const FieldGeometry& field,
                                      const CameraModel& start, double max_rms_px) {
  LineRefinement r;
  try {
    FieldLineFit fit = fitCameraToFieldLines(detectFieldLinePixels(bgr), field, start);
    if (fit.rms_px > max_rms_px) {
      r.reason = fieldLineFitAdvice(fit, false, max_rms_px);
      return r;
    }
    r.advice = fieldLineFitAdvice(fit, false, max_rms_px);
    r.fit = std::move(fit);
  } catch (const std::invalid_argument& e) {
    r.reason = e.what();
  }
  return r;
}

}  // namespace soccer_vision
