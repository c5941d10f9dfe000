// `.svct` colour table files (ColorTable::load reads files only: the bytes go through one).
#include <cstdio>
#include <string>
#include <unistd.h>

#include "fuzz_target.h"
#include "soccer_vision/segmentation/color_table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/soccer_vision_fuzz_color_table_" + std::to_string(getpid()) + ".svct";
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    const soccer_vision::ColorTable table = soccer_vision::ColorTable::load(path);
    table.classify(10, 200, 30);
  } catch (const std::exception&) {
  }
  std::remove(path.c_str());
  return 0;
}
