// Files of the installed soccer_vision package, found the ROS way (ROS_PACKAGE_PATH).
#pragma once

#include <string>

namespace soccer_vision {

// A scenario preset name ("uneven_drift") -> <package>/config/scenarios/<name>.yaml;
// anything containing a slash or ending in .yaml is returned as the path it is; "" stays
// "" (the embedded default). Throws std::runtime_error if the package cannot be found.
std::string resolveScenarioPath(const std::string& name_or_path);

}  // namespace soccer_vision
