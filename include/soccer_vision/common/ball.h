// The league's ball: an orange golf ball, 43 mm across (the SSL rules). Its centre lies
// this high above the carpet, which is where projections put it.
#pragma once

namespace soccer_vision {

inline constexpr double kBallRadius = 0.0215;  // [m]

}  // namespace soccer_vision
