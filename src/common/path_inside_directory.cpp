#include "soccer_vision/common/path_inside_directory.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace soccer_vision {

namespace fs = std::filesystem;

std::string pathInsideDirectory(const std::string& directory, const std::string& requested) {
  if (directory.empty()) throw std::invalid_argument("no allowed directory for '" + requested + "'");
  if (requested.empty()) throw std::invalid_argument("empty path");
  const fs::path path(requested);
  for (const fs::path& part : path) {
    if (part == "..") throw std::invalid_argument("'" + requested + "': '..' is not allowed");
  }
  fs::path dir = fs::weakly_canonical(fs::absolute(directory));
  if (dir.filename().empty()) dir = dir.parent_path();  // a trailing '/'
  const fs::path full = fs::weakly_canonical(path.is_absolute() ? path : dir / path);
  const auto [d, f] = std::mismatch(dir.begin(), dir.end(), full.begin(), full.end());
  if (d != dir.end() || f == full.end()) {
    throw std::invalid_argument("'" + requested + "' is outside the allowed directory " + dir.string());
  }
  return full.string();
}

}  // namespace soccer_vision
