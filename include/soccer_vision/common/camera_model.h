// Pinhole camera with plumb_bob (OpenCV k1 k2 p1 p2 k3) distortion and a pose in `field`.
// Pixel coordinates follow OpenCV/ROS: (0, 0) is the centre of the top-left pixel.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace soccer_vision {

struct FieldGeometry;

struct CameraIntrinsics {
  int width = 1280;
  int height = 1024;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 5> dist{};  // k1, k2, p1, p2, k3
};

// The largest image side any input may have (docs/robustness.md): a 16k camera, far above
// the 1280 x 1024 of the paper; bigger sizes are refused before anything is allocated.
constexpr int kMaxImageSide = 16384;
constexpr int kMaxCameras = 8;  // cameras over one field (CameraModel::defaultCamera's layouts)

// Throws std::invalid_argument naming the field for a size outside 1..kMaxImageSide, a
// focal length that is not finite and positive, or a principal point or distortion
// coefficient that is not finite (NaN or Inf once gave 0 robots with OK diagnostics).
void checkIntrinsics(const CameraIntrinsics& k);

class CameraModel {
 public:
  CameraModel() = default;
  // field_T_camera: pose of the optical frame (z forward, x right, y down) in `field`.
  CameraModel(const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& field_T_camera);

  // The built-in camera `index` of a layout of `count` cameras (1..kMaxCameras) over the
  // field: a grid of cells, one camera 4 m above each cell's centre looking straight down
  // (with a small mounting error), the image's long side along the cell's, the focal length
  // scaled from the Division B camera (800 px at 1280 x 1024 for a 4.5 x 6 m half) so that
  // the cell plus 0.35 m on each side (overlap, boundary) is in view as in Division B, with
  // moderate barrel distortion.
  // Cells: count cameras in a row along field x, or 2 rows along y for an even count >= 4
  // (4: the quarters). count 2, the default: camera 0 over x < 0, camera 1 over x > 0.
  // Throws std::invalid_argument for an index outside 0..count-1 or count outside 1..8.
  static CameraModel defaultCamera(const FieldGeometry& field, int index, int width = 1280, int height = 1024,
                                   int count = 2);

  const CameraIntrinsics& intrinsics() const { return k_; }
  const Eigen::Isometry3d& fieldTCamera() const { return field_T_camera_; }
  int width() const { return k_.width; }
  int height() const { return k_.height; }
  // Same camera at another resolution (intrinsics scaled, pose and distortion kept).
  CameraModel scaled(int width, int height) const;

  // Normalised undistorted (x/z, y/z) -> normalised distorted.
  Eigen::Vector2d distortNormalized(const Eigen::Vector2d& xy) const;
  // Inverse of distortNormalized (iterative; exact to ~1e-12 within the image).
  Eigen::Vector2d undistortNormalized(const Eigen::Vector2d& xy_distorted) const;

  // Field point -> raw (distorted) pixel; nullopt when behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_field) const;
  // Field point -> pixel of the ideal (undistorted) pinhole camera.
  std::optional<Eigen::Vector2d> projectUndistorted(const Eigen::Vector3d& p_field) const;
  // Raw pixel -> unit ray direction in `field` (origin: cameraCentre()).
  Eigen::Vector3d pixelRay(const Eigen::Vector2d& pixel) const;
  // Raw pixel -> point on the horizontal plane z = plane_z; nullopt if the ray misses it.
  std::optional<Eigen::Vector3d> pixelToField(const Eigen::Vector2d& pixel, double plane_z) const;
  Eigen::Vector3d cameraCentre() const { return field_T_camera_.translation(); }
  bool inImage(const Eigen::Vector2d& pixel, double margin = 0.0) const;
  // Field point -> raw pixel when it lies in the image (inImage with `margin`; a negative
  // margin reaches beyond the edge), else nullopt (also behind the camera).
  std::optional<Eigen::Vector2d> projectInImage(const Eigen::Vector3d& p_field, double margin = 0.0) const;
  // Whether every field point projects into the image: a robot is in view when all its
  // marker outlines are (markerOutlinePoints), as the measured rate and the simulated user
  // count it.
  bool allInImage(const std::vector<Eigen::Vector3d>& field_points) const;

 private:
  CameraIntrinsics k_;
  Eigen::Isometry3d field_T_camera_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera_T_field_ = Eigen::Isometry3d::Identity();  // its inverse, for project()
};

// The image of a horizontal disc of `radius` centred at `centre` (a robot's top): its
// centre's pixel and its radius in pixels, the farthest of 4 rim points (±radius along x
// and y) that project; `whole` when the centre and those 4 points all lie in the image.
// nullopt when the centre is behind the camera.
struct ImageDisc {
  Eigen::Vector2d centre{0, 0};
  double radius = 0;
  bool whole = false;
};
std::optional<ImageDisc> projectDisc(const CameraModel& camera, const Eigen::Vector3d& centre, double radius);

}  // namespace soccer_vision
