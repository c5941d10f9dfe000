#include "soccer_vision/ros/package_paths.h"

#include <stdexcept>

#include <ros/package.h>

namespace soccer_vision {

std::string resolveScenarioPath(const std::string& name_or_path) {
  const auto ends_with_yaml = [](const std::string& s) {
    return s.size() >= 5 && s.compare(s.size() - 5, 5, ".yaml") == 0;
  };
  if (name_or_path.empty() || name_or_path.find('/') != std::string::npos || ends_with_yaml(name_or_path)) {
    return name_or_path;
  }
  const std::string pkg = ros::package::getPath("soccer_vision");
  if (pkg.empty()) {
    throw std::runtime_error("cannot find the soccer_vision package to look up preset '" + name_or_path +
                             "'");
  }
  return pkg + "/config/scenarios/" + name_or_path + ".yaml";
}

}  // namespace soccer_vision
