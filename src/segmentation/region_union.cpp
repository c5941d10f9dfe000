#include "soccer_vision/segmentation/region_union.h"

#include <cmath>
#include <stdexcept>

#include "soccer_vision/segmentation/region_moments.h"

namespace soccer_vision {

Region regionUnion(const std::vector<const Region*>& parts) {
  if (parts.empty()) throw std::invalid_argument("regionUnion: no parts");
  Region u;
  u.color = parts.front()->color;
  u.bbox = parts.front()->bbox;
  double area = 0, cx = 0, cy = 0;
  for (const Region* p : parts) {
    area += p->area;
    cx += p->area * p->cx;
    cy += p->area * p->cy;
    u.bbox |= p->bbox;
  }
  if (area <= 0) return *parts.front();
  cx /= area;
  cy /= area;
  for (const Region* p : parts) {
    const double dx = p->cx - cx, dy = p->cy - cy, w = p->area / area;
    u.mu20 += w * (p->mu20 + dx * dx);
    u.mu11 += w * (p->mu11 + dx * dy);
    u.mu02 += w * (p->mu02 + dy * dy);
  }
  u.area = static_cast<std::uint32_t>(area);
  u.cx = cx;
  u.cy = cy;
  u.orientation = majorAxisAngle(u.mu20, u.mu11, u.mu02);
  return u;
}

}  // namespace soccer_vision
