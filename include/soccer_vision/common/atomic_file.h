// Files other processes read while they are being written: the demo's colour tables, written
// by calibrate_synthetic while each camera's segmentation waits to load them.
#pragma once

#include <cstddef>
#include <string>

namespace soccer_vision {

// Writes `size` bytes to `path` through a file beside it that is renamed over it: a reader
// sees the old file (or none) or the whole new one, never a part. Throws
// std::runtime_error naming `path` when it cannot be written.
void writeFileAtomically(const std::string& path, const void* data, std::size_t size);

}  // namespace soccer_vision
