// Things around a real field that are not robots or balls, all outside the field lines:
// people standing at the boundary (shoes and legs seen from above, often in team or ball
// colours), clothes lying on the floor and cables. Flat on the floor, static, drawn from
// the seed; the renderer paints them into the background (label: none).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/field_geometry.h"

namespace soccer_vision {

struct Distractor {
  enum class Kind { Ellipse, Cable };
  Kind kind = Kind::Ellipse;
  double x = 0, y = 0;        // m: ellipse centre; cable midpoint
  double half_length = 0.1;   // m: ellipse semi-major axis; half the cable's length
  double half_width = 0.05;   // m: ellipse semi-minor axis; half the cable's width
  double angle = 0;           // rad: direction of the major axis / of the cable
  cv::Vec3f albedo{0, 0, 0};  // linear BGR, as classAlbedo
  // Signed distance of a floor point to the shape (negative inside; approximate for ellipses).
  float sdf(float px, float py) const;
  double boundingRadius() const { return half_length + (kind == Kind::Cable ? half_width : 0.0); }
};

// `count` objects (a person counts as one: two shoes and two legs), each wholly outside
// the field lines (at least 2 cm beyond their outer edges) and within 0.5 m of the carpet.
std::vector<Distractor> distractorLayout(int count, const FieldGeometry& field, std::uint64_t seed);

// Distance from a floor point to the playing area including its lines (0 inside).
double distanceOutsideLines(const FieldGeometry& field, double x, double y);

}  // namespace soccer_vision
