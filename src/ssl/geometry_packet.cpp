#include "soccer_vision/ssl/geometry_packet.h"

#include <Eigen/Geometry>

#include "soccer_vision/ssl/units.h"

namespace soccer_vision::ssl {

namespace {

void setVector(const Eigen::Vector2d& p, ::Vector2f* out) {
  out->set_x(toMillimetres(p.x()));
  out->set_y(toMillimetres(p.y()));
}

}  // namespace

::SSL_FieldShapeType shapeType(const std::string& name) {
  ::SSL_FieldShapeType type = ::Undefined;
  // The enum's value names are the league's shape names.
  if (::SSL_FieldShapeType_Parse(name, &type)) return type;
  return ::Undefined;
}

::SSL_GeometryFieldSize fieldSize(const FieldGeometry& field, const GeometryPacketOptions& options) {
  ::SSL_GeometryFieldSize size;
  size.set_field_length(toWholeMillimetres(field.length));
  size.set_field_width(toWholeMillimetres(field.width));
  size.set_goal_width(toWholeMillimetres(field.goal_width));
  size.set_goal_depth(toWholeMillimetres(field.goal_depth));
  size.set_boundary_width(toWholeMillimetres(field.boundary));
  for (const LineSegment& l : field.lines()) {
    ::SSL_FieldLineSegment* out = size.add_field_lines();
    out->set_name(l.name);
    setVector(l.a, out->mutable_p1());
    setVector(l.b, out->mutable_p2());
    out->set_thickness(toMillimetres(field.line_width));
    out->set_type(shapeType(l.name));
  }
  for (const CircleArc& c : field.circles()) {
    ::SSL_FieldCircularArc* out = size.add_field_arcs();
    out->set_name(c.name);
    setVector(c.centre, out->mutable_center());
    out->set_radius(toMillimetres(c.radius));
    out->set_a1(static_cast<float>(c.a1));
    out->set_a2(static_cast<float>(c.a2));
    out->set_thickness(toMillimetres(field.line_width));
    out->set_type(shapeType(c.name));
  }
  size.set_penalty_area_depth(toWholeMillimetres(field.penalty_area_depth));
  size.set_penalty_area_width(toWholeMillimetres(field.penalty_area_width));
  size.set_center_circle_radius(toWholeMillimetres(field.centre_radius));
  size.set_line_thickness(toWholeMillimetres(field.line_width));
  size.set_goal_center_to_penalty_mark(toWholeMillimetres(field.penalty_mark_distance));
  size.set_goal_height(toWholeMillimetres(field.goal_height));
  size.set_ball_radius(toMillimetres(options.ball_radius));
  size.set_max_robot_radius(toMillimetres(options.max_robot_radius));
  return size;
}

::SSL_GeometryCameraCalibration cameraCalibration(int camera_id, const CameraModel& camera) {
  const CameraIntrinsics& k = camera.intrinsics();
  const Eigen::Isometry3d camera_T_field = camera.fieldTCamera().inverse();
  const Eigen::Quaterniond q(camera_T_field.rotation());
  const Eigen::Vector3d t = camera_T_field.translation();
  const Eigen::Vector3d centre = camera.cameraCentre();
  ::SSL_GeometryCameraCalibration c;
  c.set_camera_id(static_cast<std::uint32_t>(camera_id));
  c.set_focal_length(static_cast<float>((k.fx + k.fy) / 2));
  c.set_principal_point_x(static_cast<float>(k.cx));
  c.set_principal_point_y(static_cast<float>(k.cy));
  c.set_distortion(static_cast<float>(k.dist[0]));
  c.set_q0(static_cast<float>(q.x()));
  c.set_q1(static_cast<float>(q.y()));
  c.set_q2(static_cast<float>(q.z()));
  c.set_q3(static_cast<float>(q.w()));
  c.set_tx(toMillimetres(t.x()));
  c.set_ty(toMillimetres(t.y()));
  c.set_tz(toMillimetres(t.z()));
  c.set_derived_camera_world_tx(toMillimetres(centre.x()));
  c.set_derived_camera_world_ty(toMillimetres(centre.y()));
  c.set_derived_camera_world_tz(toMillimetres(centre.z()));
  c.set_pixel_image_width(static_cast<std::uint32_t>(k.width));
  c.set_pixel_image_height(static_cast<std::uint32_t>(k.height));
  return c;
}

::SSL_WrapperPacket geometryPacket(const FieldGeometry& field,
                                   const std::vector<CameraCalibrationInput>& cameras,
                                   const GeometryPacketOptions& options) {
  ::SSL_WrapperPacket packet;
  packet.set_source(::VISION_SOURCE_OTHER);
  ::SSL_GeometryData* g = packet.mutable_geometry();
  *g->mutable_field() = fieldSize(field, options);
  for (const CameraCalibrationInput& c : cameras) *g->add_calib() = cameraCalibration(c.camera_id, c.camera);
  return packet;
}

}  // namespace soccer_vision::ssl
