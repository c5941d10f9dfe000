#include "command_line.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace soccer_vision {

double parseNumber(const std::string& flag, const std::string& text) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (text.empty() || used != text.size() || !std::isfinite(v)) {
    throw std::invalid_argument(flag + " takes a number, not '" + text + "'");
  }
  return v;
}

int parseInteger(const std::string& flag, const std::string& text, int min, int max) {
  std::size_t used = 0;
  long v = 0;
  try {
    v = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (text.empty() || used != text.size() || v < min || v > max) {
    std::string range;
    if (min != INT_MIN) range += " >= " + std::to_string(min);
    if (max != INT_MAX) range += (range.empty() ? " <= " : " and <= ") + std::to_string(max);
    throw std::invalid_argument(flag + " takes an integer" + range + ", not '" + text + "'");
  }
  return static_cast<int>(v);
}

std::vector<std::string> splitList(const std::string& text, char separator) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, separator);) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

bool CommandLine::next() {
  if (index_ + 1 >= argc_) return false;
  flag_ = argv_[++index_];
  return true;
}

std::string CommandLine::value() {
  if (index_ + 1 >= argc_) throw std::invalid_argument(flag_ + " needs a value");
  return argv_[++index_];
}

}  // namespace soccer_vision
