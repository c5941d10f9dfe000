// Pattern set YAML -> the markers of every id of both teams and their heights.
#include "fuzz_target.h"
#include "soccer_vision/common/robot_pattern.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const soccer_vision::PatternSet p =
        soccer_vision::parsePatternSet(soccer_vision_fuzz::asText(data, size), "fuzz");
    for (int id = -1; id < static_cast<int>(p.ids.size()); ++id) {
      p.markers(soccer_vision::Team::Blue, id);
      p.markers(soccer_vision::Team::Yellow, id);
    }
    // A pattern loaded is one whose robots stand above the carpet: else a finding.
    if (!(p.height(soccer_vision::Team::Blue) > 0 && p.height(soccer_vision::Team::Yellow) > 0))
      __builtin_trap();
  } catch (const std::exception&) {
  }
  return 0;
}
