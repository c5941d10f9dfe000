// The league's detection and geometry packets are in mm, its tracked packets in m; ours in m.
#pragma once

#include <cmath>

namespace soccer_vision::ssl {

inline float toMillimetres(double metres) { return static_cast<float>(metres * 1000.0); }
// The geometry's integer fields: the nearest whole mm.
inline int toWholeMillimetres(double metres) { return static_cast<int>(std::lround(metres * 1000.0)); }

}  // namespace soccer_vision::ssl
