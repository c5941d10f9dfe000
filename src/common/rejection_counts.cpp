#include "soccer_vision/common/rejection_counts.h"

namespace soccer_vision {

const char* rejectionCauseName(RejectionCause cause) {
  switch (cause) {
    case RejectionCause::Projection:
      return "projection";
    case RejectionCause::Unpaired:
      return "unpaired";
    case RejectionCause::Incomplete:
      return "incomplete";
    case RejectionCause::Axis:
      return "axis";
    case RejectionCause::Gate:
      return "gate";
    case RejectionCause::Id:
      return "id";
    case RejectionCause::Area:
      return "area";
    case RejectionCause::Confidence:
      return "confidence";
    case RejectionCause::Conflict:
      return "conflict";
    case RejectionCause::BallOnRobot:
      return "ball_on_robot";
    case RejectionCause::BallOffField:
      return "ball_off_field";
    case RejectionCause::BallArea:
      return "ball_area";
    case RejectionCause::BallShape:
      return "ball_shape";
    case RejectionCause::BallOnBlob:
      return "ball_on_blob";
    case RejectionCause::BallConfidence:
      return "ball_confidence";
    case RejectionCause::BallSurplus:
      return "ball_surplus";
    case RejectionCause::kCount:
      break;
  }
  return "unknown";
}

std::string RejectionCounts::summary() const {
  std::string out;
  for (int i = 0; i < kNumRejectionCauses; ++i) {
    if (counts[i] == 0) continue;
    if (!out.empty()) out += ", ";
    out += rejectionCauseName(static_cast<RejectionCause>(i));
    out += " " + std::to_string(counts[i]);
  }
  return out.empty() ? "none" : out;
}

}  // namespace soccer_vision
