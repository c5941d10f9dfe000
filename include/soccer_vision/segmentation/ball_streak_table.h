// The ball's streak (issue 14): a ball kicked at 12 m/s moves 72 mm during a 6 ms exposure,
// more than its 43 mm, so no pixel of its streak shows it for more than 60 % of the
// exposure; the rest of the time that pixel sees the carpet. The colour table's orange
// reaches only a 10 % carpet mixture (ColorTableParams::ball_carpet_mix: further, a yellow
// print under a warm lamp and a real frame's red dot turn orange), so such a streak has no
// orange region. In the primary ball's window while the ball is seen
// (SearchPlan::ball_streak_rects) the streak table classifies instead: orange is every colour near the
// mixture of the ball's and the carpet's mean colours (the table's statistics of their valid samples) with at
// least `min_ball_share` of the ball, mixed in linear light (a sensor integrating the exposure) or in the
// encoded values (a linear camera): within `tolerance` × the distance between the two colours, in 8-bit RGB.
// The carpet's cells stay the carpet's.
#pragma once

#include <optional>

#include "soccer_vision/segmentation/color_table.h"

namespace soccer_vision {

struct BallStreakParams {
  double min_ball_share = 0.3;  // of the exposure; a 12 m/s streak's middle shows 0.6
  double tolerance = 0.12;      // × |ball − carpet| in RGB: carpet texture, noise, prints
  double gamma = 2.2;           // of the camera's encoding, for the linear-light mixture

  void validate() const;  // throws std::invalid_argument
};

// A table of the same quantisation and illumination maps in which Orange holds the
// table's orange cells and the streak's, every other cell None; nullopt when the table has
// no valid samples of the ball or the carpet (no mixture line to follow).
std::optional<ColorTable> ballStreakTable(const ColorTable& table, const BallStreakParams& params = {});

}  // namespace soccer_vision
