// Scenario YAML (make_scenario, the synthetic CameraDriver).
#include "fuzz_target.h"
#include "soccer_vision/simulation/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    soccer_vision::parseScenario(soccer_vision_fuzz::asText(data, size), "fuzz");
  } catch (const std::exception&) {
  }
  return 0;
}
