// Field geometry YAML (config/fields/, the Identification and Tracking nodelets' ~field).
#include "fuzz_target.h"
#include "soccer_vision/common/field_geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    soccer_vision::parseFieldGeometry(soccer_vision_fuzz::asText(data, size), "fuzz");
  } catch (const std::exception&) {
  }
  return 0;
}
