#include "soccer_vision/common/atomic_file.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace soccer_vision {

void writeFileAtomically(const std::string& path, const void* data, std::size_t size) {
  // Beside it (rename is atomic within a file system), named per process: two writers never
  // share the temporary file.
  const std::string temporary = path + ".tmp" + std::to_string(::getpid());
  std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw std::runtime_error(path + ": cannot write file");
  }
}

}  // namespace soccer_vision
