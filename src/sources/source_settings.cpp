#include "soccer_vision/sources/source_settings.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace soccer_vision {

bool SettingsReader::has(const std::string& key) const {
  auto it = settings_.find(key);
  return it != settings_.end() && !it->second.empty();
}

std::string SettingsReader::text(const std::string& key, const std::string& fallback) const {
  auto it = settings_.find(key);
  return it == settings_.end() || it->second.empty() ? fallback : it->second;
}

bool SettingsReader::flag(const std::string& key, bool fallback) {
  if (!has(key)) return fallback;
  std::string v = text(key);
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  if (v == "true" || v == "1" || v == "yes") return true;
  if (v == "false" || v == "0" || v == "no") return false;
  if (error_.empty()) error_ = "setting " + key + " = '" + text(key) + "' is not a boolean";
  return fallback;
}

double SettingsReader::number(const std::string& key, double fallback) {
  if (!has(key)) return fallback;
  const std::string v = text(key);
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || *end != '\0' || !std::isfinite(d)) {
    if (error_.empty()) error_ = "setting " + key + " = '" + v + "' is not a number";
    return fallback;
  }
  return d;
}

}  // namespace soccer_vision
