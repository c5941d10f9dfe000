// Camera pose YAML (calibrate_field's output, Identification's ~camera_pose).
#include "fuzz_target.h"
#include "soccer_vision/common/camera_pose_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    soccer_vision::parseCameraPoseFile(soccer_vision_fuzz::asText(data, size), "fuzz");
  } catch (const std::exception&) {
  }
  return 0;
}
