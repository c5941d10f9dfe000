// Summary figures of a sample that may contain NaN/inf (missing values), used by the
// evaluation figures' legends (p50/p99 of stage times, RMS of errors).
#pragma once

#include <vector>

namespace soccer_vision {

// The finite values of the sample, in their order.
std::vector<double> finiteValues(const std::vector<double>& values);

// p-th percentile (p in [0, 100]) of the finite values, linear between order statistics
// (p = 50 of {1, 2, 3, 4} is 2.5). NaN for no finite value; throws std::invalid_argument
// for p outside [0, 100].
double percentile(const std::vector<double>& values, double p);

// sqrt(mean(v²)) over the finite values; NaN for none.
double rootMeanSquare(const std::vector<double>& values);

}  // namespace soccer_vision
