#include "soccer_vision/common/camera_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "soccer_vision/common/field_geometry.h"

namespace soccer_vision {

CameraModel::CameraModel(const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& field_T_camera)
    : k_(intrinsics), field_T_camera_(field_T_camera), camera_T_field_(field_T_camera.inverse()) {}

CameraModel CameraModel::defaultCamera(const FieldGeometry& field, int index, int width, int height,
                                       int count) {
  if (count < 1 || count > kMaxCameras) {
    throw std::invalid_argument("camera layout: " + std::to_string(count) + " cameras (1.." +
                                std::to_string(kMaxCameras) + ")");
  }
  if (index < 0 || index >= count) {
    throw std::invalid_argument("camera layout: no camera " + std::to_string(index) + " among " +
                                std::to_string(count));
  }
  // The cell of the field this camera watches: `columns` along x, `rows` along y.
  const int rows = (count >= 4 && count % 2 == 0) ? 2 : 1;
  const int columns = count / rows;
  const int column = index % columns, row = index / columns;
  const double cell_x = field.length / columns, cell_y = field.width / rows;
  const double centre_x = -field.halfLength() + (column + 0.5) * cell_x;
  const double centre_y = -field.halfWidth() + (row + 0.5) * cell_y;

  // Designed at 1280x1024 for Division B's half (4.5 m along the 1024 px, 6 m along the
  // 1280 px): f = 800 px at 4 m gives ~5 mm per pixel at the image centre and, with the
  // barrel distortion, covers the half plus the 0.3 m boundary on one side and 0.3 m of
  // overlap on the other. Other cells keep that view of the cell plus 0.35 m on each side.
  const double long_side = std::max(cell_x, cell_y), short_side = std::min(cell_x, cell_y);
  CameraIntrinsics k;
  k.width = 1280;
  k.height = 1024;
  k.fx = k.fy = 800.0 * std::min(6.7 / (long_side + 0.7), 5.2 / (short_side + 0.7));
  k.cx = 639.5;
  k.cy = 511.5;
  k.dist = {-0.12, 0.02, 0.0, 0.0, 0.0};  // barrel, like the wide-angle lenses of real fields

  // Optical frame looking straight down: z_opt = -z_field; the image's long side (u) along
  // the cell's: x_opt = +y_field, y_opt = +x_field for cells longer along y (Division B's
  // halves), x_opt = +x_field, y_opt = -y_field otherwise. Then a small mounting error, as no
  // real camera hangs perfectly, mirrored between the two ends of the field.
  Eigen::Matrix3d down;
  if (cell_y >= cell_x) {
    down.col(0) = Eigen::Vector3d::UnitY();
    down.col(1) = Eigen::Vector3d::UnitX();
  } else {
    down.col(0) = Eigen::Vector3d::UnitX();
    down.col(1) = -Eigen::Vector3d::UnitY();
  }
  down.col(2) = -Eigen::Vector3d::UnitZ();
  const double side = centre_x < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d mount = (Eigen::AngleAxisd(side * 0.015, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(0.010, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(-side * 0.008, Eigen::Vector3d::UnitX()))
                                    .toRotationMatrix();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = mount * down;
  pose.translation() = Eigen::Vector3d(centre_x + side * 0.01, centre_y + 0.02, 4.0);
  CameraModel model(k, pose);
  return (width == k.width && height == k.height) ? model : model.scaled(width, height);
}

CameraModel CameraModel::scaled(int width, int height) const {
  const double sx = static_cast<double>(width) / k_.width;
  const double sy = static_cast<double>(height) / k_.height;
  CameraIntrinsics k = k_;
  k.width = width;
  k.height = height;
  k.fx *= sx;
  k.fy *= sy;
  // Pixel centres: continuous coordinate c maps to (c + 0.5) * s - 0.5.
  k.cx = (k_.cx + 0.5) * sx - 0.5;
  k.cy = (k_.cy + 0.5) * sy - 0.5;
  return CameraModel(k, field_T_camera_);
}

Eigen::Vector2d CameraModel::distortNormalized(const Eigen::Vector2d& xy) const {
  const auto& d = k_.dist;
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
  return {x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x),
          y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y};
}

Eigen::Vector2d CameraModel::undistortNormalized(const Eigen::Vector2d& xy_distorted) const {
  // Newton's method on distort(p) = target with the analytic Jacobian: converges in a few
  // steps everywhere the distortion is monotonic (the whole image for sane lenses).
  const auto& d = k_.dist;
  Eigen::Vector2d p = xy_distorted;
  for (int it = 0; it < 30; ++it) {
    const Eigen::Vector2d err = distortNormalized(p) - xy_distorted;
    if (err.squaredNorm() < 1e-28) break;
    const double x = p.x(), y = p.y(), r2 = x * x + y * y;
    const double radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
    const double dradial_dr2 = d[0] + r2 * (2 * d[1] + 3 * r2 * d[4]);
    Eigen::Matrix2d j;
    j(0, 0) = radial + 2 * x * x * dradial_dr2 + 2 * d[2] * y + 6 * d[3] * x;
    j(0, 1) = 2 * x * y * dradial_dr2 + 2 * d[2] * x + 2 * d[3] * y;
    j(1, 0) = 2 * x * y * dradial_dr2 + 2 * d[2] * x + 2 * d[3] * y;
    j(1, 1) = radial + 2 * y * y * dradial_dr2 + 6 * d[2] * y + 2 * d[3] * x;
    p -= j.inverse() * err;
  }
  return p;
}

std::optional<Eigen::Vector2d> CameraModel::projectUndistorted(const Eigen::Vector3d& p_field) const {
  const Eigen::Vector3d pc = camera_T_field_ * p_field;
  if (pc.z() <= 1e-9) return std::nullopt;
  return Eigen::Vector2d(k_.fx * pc.x() / pc.z() + k_.cx, k_.fy * pc.y() / pc.z() + k_.cy);
}

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& p_field) const {
  const Eigen::Vector3d pc = camera_T_field_ * p_field;
  if (pc.z() <= 1e-9) return std::nullopt;
  const Eigen::Vector2d xy = distortNormalized({pc.x() / pc.z(), pc.y() / pc.z()});
  return Eigen::Vector2d(k_.fx * xy.x() + k_.cx, k_.fy * xy.y() + k_.cy);
}

Eigen::Vector3d CameraModel::pixelRay(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d xy = undistortNormalized({(pixel.x() - k_.cx) / k_.fx, (pixel.y() - k_.cy) / k_.fy});
  return (field_T_camera_.linear() * Eigen::Vector3d(xy.x(), xy.y(), 1.0)).normalized();
}

std::optional<Eigen::Vector3d> CameraModel::pixelToField(const Eigen::Vector2d& pixel, double plane_z) const {
  const Eigen::Vector3d ray = pixelRay(pixel);
  const Eigen::Vector3d c = cameraCentre();
  if (std::abs(ray.z()) < 1e-12) return std::nullopt;
  const double t = (plane_z - c.z()) / ray.z();
  if (t <= 0) return std::nullopt;
  return c + t * ray;
}

bool CameraModel::inImage(const Eigen::Vector2d& pixel, double margin) const {
  return pixel.x() >= -0.5 + margin && pixel.y() >= -0.5 + margin && pixel.x() <= k_.width - 0.5 - margin &&
         pixel.y() <= k_.height - 0.5 - margin;
}

std::optional<Eigen::Vector2d> CameraModel::projectInImage(const Eigen::Vector3d& p_field,
                                                           double margin) const {
  std::optional<Eigen::Vector2d> px = project(p_field);
  if (px && !inImage(*px, margin)) px.reset();
  return px;
}

bool CameraModel::allInImage(const std::vector<Eigen::Vector3d>& field_points) const {
  return std::all_of(field_points.begin(), field_points.end(),
                     [&](const Eigen::Vector3d& p) { return projectInImage(p).has_value(); });
}

void checkIntrinsics(const CameraIntrinsics& k) {
  if (k.width < 1 || k.width > kMaxImageSide || k.height < 1 || k.height > kMaxImageSide) {
    throw std::invalid_argument("image size " + std::to_string(k.width) + "x" + std::to_string(k.height) +
                                " outside 1.." + std::to_string(kMaxImageSide));
  }
  if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || k.fx <= 0 || k.fy <= 0) {
    throw std::invalid_argument("focal length (fx " + std::to_string(k.fx) + ", fy " + std::to_string(k.fy) +
                                ") must be finite and positive");
  }
  if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
    throw std::invalid_argument("principal point is not finite");
  for (std::size_t i = 0; i < k.dist.size(); ++i) {
    if (!std::isfinite(k.dist[i]))
      throw std::invalid_argument("distortion coefficient " + std::to_string(i) + " is not finite");
  }
}

std::optional<ImageDisc> projectDisc(const CameraModel& camera, const Eigen::Vector3d& centre,
                                     double radius) {
  const auto middle = camera.project(centre);
  if (!middle) return std::nullopt;
  ImageDisc disc{*middle, 0, camera.inImage(*middle)};
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(radius, 0, 0), Eigen::Vector3d(-radius, 0, 0),
                                        Eigen::Vector3d(0, radius, 0), Eigen::Vector3d(0, -radius, 0)}) {
    const auto rim = camera.project(centre + offset);
    disc.whole = disc.whole && rim && camera.inImage(*rim);
    if (rim) disc.radius = std::max(disc.radius, (*rim - *middle).norm());
  }
  return disc;
}

}  // namespace soccer_vision
