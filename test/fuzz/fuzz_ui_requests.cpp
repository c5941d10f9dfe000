// The calibration UI's request bodies (calibration_ui_server.cpp): the bytes as a body, parsed
// as JSON within the limits, then as colour samples and as field correspondences of a
// 1280 x 1024 frame. Only a result or a UiRequestError (the 400 the client sees) may come out.
#include "fuzz_target.h"
#include "soccer_vision/ui/ui_requests.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const soccer_vision::UiRequestLimits limits;
  try {
    const nlohmann::json body = soccer_vision::parseJsonBody(soccer_vision_fuzz::asText(data, size), limits);
    try {
      soccer_vision::parseSamplesRequest(body, 1280, 1024, limits);
    } catch (const soccer_vision::UiRequestError&) {
    }
    soccer_vision::parseCorrespondencesRequest(body, 1280, 1024, limits);
  } catch (const soccer_vision::UiRequestError&) {
  }
  return 0;
}
