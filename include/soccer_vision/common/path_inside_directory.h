// Files a remote request may write: only inside one allowed directory, so that a service
// call cannot overwrite an unrelated file the process can write.
#pragma once

#include <string>

namespace soccer_vision {

// The absolute path `requested` names inside `directory` (a relative path is taken relative
// to it; symbolic links of existing parts are resolved). Throws std::invalid_argument when
// `requested` is empty, has a `..` component, or lies outside `directory` (or is it).
std::string pathInsideDirectory(const std::string& directory, const std::string& requested);

}  // namespace soccer_vision
