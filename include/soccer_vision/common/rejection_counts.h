// Why identification did not report a candidate, counted by cause: a robot candidate is a
// team-colour region that ends in no reported robot, a ball candidate an orange cluster that
// ends in no reported ball. Nothing is dropped silently: `detect` prints these counts and the
// Identification nodelet's diagnostics sum them (a too strict pattern or gate shows up as one
// cause growing).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace soccer_vision {

enum class RejectionCause {
  Projection,      // region (or a robot's expected outline) not on the plane through the camera model
  Unpaired,        // team region without an id-colour region at any slot's distance
  Incomplete,      // more id markers missing than max_missing_markers
  Axis,            // the team tag's axis contradicts the markers' heading (axis_gate_deg)
  Gate,            // a marker farther than marker_gate from where the fitted pose puts it
  Id,              // the colours seen fit no id of the pattern, or more than one
  Area,            // a marker's pixel area outside [1/area_ratio_gate, area_ratio_gate] x expected
  Confidence,      // plausible, but confidence below min_confidence
  Conflict,        // its regions or its (team, id) went to a better robot
  BallOnRobot,     // ball cluster inside an identified robot's top in the image
  BallOffField,    // ball cluster beyond the carpet + field_margin
  BallArea,        // ball area outside [area_ratio_min, area_ratio_max] x expected
  BallShape,       // ball width outside [width_ratio_min, width_ratio_max] x expected, or longer than
                   // max_elongation
  BallOnBlob,      // ball cluster beside a blob of a marker colour many balls large: part of a shoe
  BallOnLine,      // thin ball cluster on a painted line or the carpet's edge: its colour fringe
  BallConfidence,  // ball confidence below min_confidence
  BallSurplus,     // a plausible ball beyond max_candidates
  kCount
};

constexpr int kNumRejectionCauses = static_cast<int>(RejectionCause::kCount);

// Stable lower-case names ("area", "ball_area", ...): JSON keys and diagnostics labels.
const char* rejectionCauseName(RejectionCause cause);
// The cause of a name as rejectionCauseName writes it; nullopt for an unknown name.
std::optional<RejectionCause> parseRejectionCause(std::string_view name);

struct RejectionCounts {
  std::array<long, kNumRejectionCauses> counts{};

  void add(RejectionCause cause, long n = 1) { counts[static_cast<int>(cause)] += n; }
  long operator[](RejectionCause cause) const { return counts[static_cast<int>(cause)]; }
  long total() const {
    long t = 0;
    for (long c : counts) t += c;
    return t;
  }
  RejectionCounts& operator+=(const RejectionCounts& o) {
    for (int i = 0; i < kNumRejectionCauses; ++i) counts[i] += o.counts[i];
    return *this;
  }
  // Each cause's name (rejectionCauseName) and count, in the enum's order; with
  // `counted_only` the causes with a count only. The one listing that JSON, diagnostics
  // and summary() are made from.
  std::vector<std::pair<const char*, long>> named(bool counted_only) const;
  // "area 2, confidence 1" (causes with a count only); "none" when nothing was rejected.
  std::string summary() const;
};

}  // namespace soccer_vision
