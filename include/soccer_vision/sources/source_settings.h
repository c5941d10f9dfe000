// Typed reading of FrameSourceOptions::settings (strings set by the CameraDriver from its
// parameters): each back-end reads its keys through one SettingsReader and reports the first
// malformed value as its open() error.
#pragma once

#include <map>
#include <string>

namespace soccer_vision {

class SettingsReader {
 public:
  explicit SettingsReader(const std::map<std::string, std::string>& settings) : settings_(settings) {}

  bool has(const std::string& key) const;
  std::string text(const std::string& key, const std::string& fallback = "") const;
  // "true"/"false"/"1"/"0"/"yes"/"no"; anything else records an error and gives `fallback`.
  bool flag(const std::string& key, bool fallback);
  // A finite number; anything else records an error and gives `fallback`.
  double number(const std::string& key, double fallback);

  bool ok() const { return error_.empty(); }
  // The first malformed setting, e.g. "setting loop = 'maybe' is not a boolean".
  const std::string& error() const { return error_; }

 private:
  const std::map<std::string, std::string>& settings_;
  std::string error_;
};

}  // namespace soccer_vision
