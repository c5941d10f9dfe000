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
    case RejectionCause::BallOnLine:
      return "ball_on_line";
    case RejectionCause::BallConfidence:
      return "ball_confidence";
    case RejectionCause::BallSurplus:
      return "ball_surplus";
    case RejectionCause::kCount:
      break;
  }
  return "unknown";
}

std::optional<RejectionCause> parseRejectionCause(std::string_view name) {
  for (int c = 0; c < kNumRejectionCauses; ++c) {
    if (name == rejectionCauseName(static_cast<RejectionCause>(c))) return static_cast<RejectionCause>(c);
  }
  return std::nullopt;
}

std::vector<std::pair<const char*, long>> RejectionCounts::named(bool counted_only) const {
  std::vector<std::pair<const char*, long>> out;
  for (int i = 0; i < kNumRejectionCauses; ++i) {
    if (counted_only && counts[i] == 0) continue;
    out.emplace_back(rejectionCauseName(static_cast<RejectionCause>(i)), counts[i]);
  }
  return out;
}

std::string RejectionCounts::summary() const {
  std::string out;
  for (const auto& [name, count] : named(true)) {
    if (!out.empty()) out += ", ";
    out += std::string(name) + " " + std::to_string(count);
  }
  return out.empty() ? "none" : out;
}

}  // namespace soccer_vision
