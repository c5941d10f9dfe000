// The .proto files against the league's wire format (field numbers and types of the issue's
// list, proto2): a renumbered or retyped field breaks every existing SSL client.
#include <map>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <gtest/gtest.h>

#include "ssl_vision_wrapper.pb.h"
#include "ssl_vision_wrapper_tracked.pb.h"

namespace {

using google::protobuf::Descriptor;
using google::protobuf::DescriptorPool;
using google::protobuf::FieldDescriptor;

struct Field {
  const char* message;
  const char* name;
  int number;
  FieldDescriptor::Type type;
  FieldDescriptor::Label label;
};

constexpr auto kReq = FieldDescriptor::LABEL_REQUIRED;
constexpr auto kOpt = FieldDescriptor::LABEL_OPTIONAL;
constexpr auto kRep = FieldDescriptor::LABEL_REPEATED;
constexpr auto kFloat = FieldDescriptor::TYPE_FLOAT;
constexpr auto kDouble = FieldDescriptor::TYPE_DOUBLE;
constexpr auto kU32 = FieldDescriptor::TYPE_UINT32;
constexpr auto kI32 = FieldDescriptor::TYPE_INT32;
constexpr auto kMsg = FieldDescriptor::TYPE_MESSAGE;
constexpr auto kEnum = FieldDescriptor::TYPE_ENUM;
constexpr auto kString = FieldDescriptor::TYPE_STRING;

const std::vector<Field> kFields = {
    {"SSL_WrapperPacket", "detection", 1, kMsg, kOpt},
    {"SSL_WrapperPacket", "geometry", 2, kMsg, kOpt},
    {"SSL_WrapperPacket", "source", 3, kEnum, kOpt},
    {"SSL_DetectionFrame", "frame_number", 1, kU32, kReq},
    {"SSL_DetectionFrame", "t_capture", 2, kDouble, kReq},
    {"SSL_DetectionFrame", "t_sent", 3, kDouble, kReq},
    {"SSL_DetectionFrame", "t_capture_camera", 8, kDouble, kOpt},
    {"SSL_DetectionFrame", "camera_id", 4, kU32, kReq},
    {"SSL_DetectionFrame", "balls", 5, kMsg, kRep},
    {"SSL_DetectionFrame", "robots_yellow", 6, kMsg, kRep},
    {"SSL_DetectionFrame", "robots_blue", 7, kMsg, kRep},
    {"SSL_DetectionBall", "confidence", 1, kFloat, kReq},
    {"SSL_DetectionBall", "area", 2, kU32, kOpt},
    {"SSL_DetectionBall", "x", 3, kFloat, kReq},
    {"SSL_DetectionBall", "y", 4, kFloat, kReq},
    {"SSL_DetectionBall", "z", 5, kFloat, kOpt},
    {"SSL_DetectionBall", "pixel_x", 6, kFloat, kReq},
    {"SSL_DetectionBall", "pixel_y", 7, kFloat, kReq},
    {"SSL_DetectionRobot", "confidence", 1, kFloat, kReq},
    {"SSL_DetectionRobot", "robot_id", 2, kU32, kOpt},
    {"SSL_DetectionRobot", "x", 3, kFloat, kReq},
    {"SSL_DetectionRobot", "y", 4, kFloat, kReq},
    {"SSL_DetectionRobot", "orientation", 5, kFloat, kOpt},
    {"SSL_DetectionRobot", "pixel_x", 6, kFloat, kReq},
    {"SSL_DetectionRobot", "pixel_y", 7, kFloat, kReq},
    {"SSL_DetectionRobot", "height", 8, kFloat, kOpt},
    {"SSL_GeometryData", "field", 1, kMsg, kReq},
    {"SSL_GeometryData", "calib", 2, kMsg, kRep},
    {"SSL_GeometryFieldSize", "field_length", 1, kI32, kReq},
    {"SSL_GeometryFieldSize", "field_width", 2, kI32, kReq},
    {"SSL_GeometryFieldSize", "goal_width", 3, kI32, kReq},
    {"SSL_GeometryFieldSize", "goal_depth", 4, kI32, kReq},
    {"SSL_GeometryFieldSize", "boundary_width", 5, kI32, kReq},
    {"SSL_GeometryFieldSize", "field_lines", 6, kMsg, kRep},
    {"SSL_GeometryFieldSize", "field_arcs", 7, kMsg, kRep},
    {"SSL_GeometryFieldSize", "penalty_area_depth", 8, kI32, kOpt},
    {"SSL_GeometryFieldSize", "penalty_area_width", 9, kI32, kOpt},
    {"SSL_GeometryFieldSize", "center_circle_radius", 10, kI32, kOpt},
    {"SSL_GeometryFieldSize", "line_thickness", 11, kI32, kOpt},
    {"SSL_GeometryFieldSize", "goal_center_to_penalty_mark", 12, kI32, kOpt},
    {"SSL_GeometryFieldSize", "goal_height", 13, kI32, kOpt},
    {"SSL_GeometryFieldSize", "ball_radius", 14, kFloat, kOpt},
    {"SSL_GeometryFieldSize", "max_robot_radius", 15, kFloat, kOpt},
    {"SSL_FieldLineSegment", "name", 1, kString, kReq},
    {"SSL_FieldLineSegment", "p1", 2, kMsg, kReq},
    {"SSL_FieldLineSegment", "p2", 3, kMsg, kReq},
    {"SSL_FieldLineSegment", "thickness", 4, kFloat, kReq},
    {"SSL_FieldLineSegment", "type", 5, kEnum, kOpt},
    {"SSL_FieldCircularArc", "name", 1, kString, kReq},
    {"SSL_FieldCircularArc", "center", 2, kMsg, kReq},
    {"SSL_FieldCircularArc", "radius", 3, kFloat, kReq},
    {"SSL_FieldCircularArc", "a1", 4, kFloat, kReq},
    {"SSL_FieldCircularArc", "a2", 5, kFloat, kReq},
    {"SSL_FieldCircularArc", "thickness", 6, kFloat, kReq},
    {"SSL_FieldCircularArc", "type", 7, kEnum, kOpt},
    {"Vector2f", "x", 1, kFloat, kReq},
    {"Vector2f", "y", 2, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "camera_id", 1, kU32, kReq},
    {"SSL_GeometryCameraCalibration", "focal_length", 2, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "principal_point_x", 3, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "principal_point_y", 4, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "distortion", 5, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "q0", 6, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "q1", 7, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "q2", 8, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "q3", 9, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "tx", 10, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "ty", 11, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "tz", 12, kFloat, kReq},
    {"SSL_GeometryCameraCalibration", "derived_camera_world_tx", 13, kFloat, kOpt},
    {"SSL_GeometryCameraCalibration", "derived_camera_world_ty", 14, kFloat, kOpt},
    {"SSL_GeometryCameraCalibration", "derived_camera_world_tz", 15, kFloat, kOpt},
    {"SSL_GeometryCameraCalibration", "pixel_image_width", 16, kU32, kOpt},
    {"SSL_GeometryCameraCalibration", "pixel_image_height", 17, kU32, kOpt},
    {"TrackerWrapperPacket", "uuid", 1, kString, kReq},
    {"TrackerWrapperPacket", "source_name", 2, kString, kOpt},
    {"TrackerWrapperPacket", "tracked_frame", 3, kMsg, kOpt},
    {"TrackedFrame", "frame_number", 1, kU32, kReq},
    {"TrackedFrame", "timestamp", 2, kDouble, kReq},
    {"TrackedFrame", "balls", 3, kMsg, kRep},
    {"TrackedFrame", "robots", 4, kMsg, kRep},
    {"TrackedFrame", "kicked_ball", 5, kMsg, kOpt},
    {"TrackedFrame", "capabilities", 6, kEnum, kRep},
    {"TrackedBall", "pos", 1, kMsg, kReq},
    {"TrackedBall", "vel", 2, kMsg, kOpt},
    {"TrackedBall", "visibility", 3, kFloat, kOpt},
    {"TrackedRobot", "robot_id", 1, kMsg, kReq},
    {"TrackedRobot", "pos", 2, kMsg, kReq},
    {"TrackedRobot", "orientation", 3, kFloat, kReq},
    {"TrackedRobot", "vel", 4, kMsg, kOpt},
    {"TrackedRobot", "vel_angular", 5, kFloat, kOpt},
    {"TrackedRobot", "visibility", 6, kFloat, kOpt},
    {"KickedBall", "pos", 1, kMsg, kReq},
    {"KickedBall", "vel", 2, kMsg, kReq},
    {"KickedBall", "start_timestamp", 3, kDouble, kReq},
    {"KickedBall", "stop_timestamp", 4, kDouble, kOpt},
    {"KickedBall", "stop_pos", 5, kMsg, kOpt},
    {"KickedBall", "robot_id", 6, kMsg, kOpt},
    {"RobotId", "id", 1, kU32, kOpt},
    {"RobotId", "team_color", 2, kEnum, kOpt},
    {"Vector2", "x", 1, kFloat, kReq},
    {"Vector2", "y", 2, kFloat, kReq},
    {"Vector3", "x", 1, kFloat, kReq},
    {"Vector3", "y", 2, kFloat, kReq},
    {"Vector3", "z", 3, kFloat, kReq},
};

}  // namespace

TEST(SslWireFormat, EveryFieldHasTheLeaguesNumberTypeAndLabel) {
  // Referencing the generated classes links their descriptors into the pool.
  ASSERT_NE(SSL_WrapperPacket::descriptor(), nullptr);
  ASSERT_NE(TrackerWrapperPacket::descriptor(), nullptr);
  const DescriptorPool* pool = DescriptorPool::generated_pool();
  for (const Field& f : kFields) {
    SCOPED_TRACE(std::string(f.message) + "." + f.name);
    const Descriptor* message = pool->FindMessageTypeByName(f.message);
    ASSERT_NE(message, nullptr);
    const FieldDescriptor* field = message->FindFieldByName(f.name);
    ASSERT_NE(field, nullptr);
    EXPECT_EQ(field->number(), f.number);
    EXPECT_EQ(field->type(), f.type);
    EXPECT_EQ(field->label(), f.label);
  }
}

TEST(SslWireFormat, EveryMessageHasOnlyTheListedFields) {
  const DescriptorPool* pool = DescriptorPool::generated_pool();
  std::map<std::string, int> listed;
  for (const Field& f : kFields) ++listed[f.message];
  for (const auto& [name, count] : listed) {
    const Descriptor* message = pool->FindMessageTypeByName(name);
    ASSERT_NE(message, nullptr) << name;
    EXPECT_EQ(message->field_count(), count) << name;
  }
}

TEST(SslWireFormat, EnumNumbersAreTheLeagues) {
  EXPECT_EQ(VISION_SOURCE_OTHER, 1);
  EXPECT_EQ(VISION_SOURCE_ERFORCE_SIM, 5);
  EXPECT_EQ(CenterCircle, 1);
  EXPECT_EQ(CenterLine, 7);
  EXPECT_EQ(RightFieldRightPenaltyStretch, 13);
  EXPECT_EQ(TEAM_YELLOW, 1);
  EXPECT_EQ(TEAM_BLUE, 2);
  EXPECT_EQ(CAPABILITY_DETECT_FLYING_BALLS, 1);
  EXPECT_EQ(CAPABILITY_DETECT_KICKED_BALLS, 3);
}

TEST(SslWireFormat, WrapperSerialisesToTheLeaguesBytes) {
  // A detection frame of camera 2, frame 7, t_capture 1.0, t_sent 2.0 and source OTHER, byte by
  // byte: tag (field << 3 | wire type), then the value.
  SSL_WrapperPacket packet;
  SSL_DetectionFrame* d = packet.mutable_detection();
  d->set_frame_number(7);
  d->set_t_capture(1.0);
  d->set_t_sent(2.0);
  d->set_camera_id(2);
  packet.set_source(VISION_SOURCE_OTHER);
  const std::string expected(
      "\x0a\x16"                              // 1 detection, length-delimited, 22 bytes
      "\x08\x07"                              // 1 frame_number = 7 (varint)
      "\x11\x00\x00\x00\x00\x00\x00\xf0\x3f"  // 2 t_capture = 1.0 (64-bit)
      "\x19\x00\x00\x00\x00\x00\x00\x00\x40"  // 3 t_sent = 2.0 (64-bit)
      "\x20\x02"                              // 4 camera_id = 2
      "\x18\x01",                             // 3 source = OTHER (varint)
      26);
  EXPECT_EQ(packet.SerializeAsString(), expected);
}
