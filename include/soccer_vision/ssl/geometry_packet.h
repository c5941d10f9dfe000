// The field and the cameras as an SSL-Vision geometry packet (docs/ssl.md): dimensions in
// whole mm, the painted lines and arcs with their shape types, one calibration per camera.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "ssl_vision_wrapper.pb.h"

namespace soccer_vision::ssl {

struct GeometryPacketOptions {
  double ball_radius = kBallRadius;  // [m]
  double max_robot_radius = 0.09;    // [m]
};

struct CameraCalibrationInput {
  int camera_id = 0;
  CameraModel camera;
};

// The league's shape type of a line or arc named as SSL-Vision names them ("TopTouchLine",
// "CenterCircle", ...); Undefined for other names (custom fields).
::SSL_FieldShapeType shapeType(const std::string& name);

::SSL_GeometryFieldSize fieldSize(const FieldGeometry& field, const GeometryPacketOptions& options = {});

// SSL-Vision's camera model: one focal length (the mean of fx and fy) [px], the principal point
// [px], one radial distortion coefficient on normalised coordinates (k1; our k2, k3, p1, p2 have
// no place), and the rotation q0..q3 (x, y, z, w) and translation tx, ty, tz [mm] that map a
// field point into the optical frame; derived_camera_world_t* is the camera centre in the field.
::SSL_GeometryCameraCalibration cameraCalibration(int camera_id, const CameraModel& camera);

::SSL_WrapperPacket geometryPacket(const FieldGeometry& field,
                                   const std::vector<CameraCalibrationInput>& cameras,
                                   const GeometryPacketOptions& options = {});

}  // namespace soccer_vision::ssl
