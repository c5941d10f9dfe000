// The calibration UI's requests: JSON bodies parsed and checked before anything reaches
// the running system. Every error is a UiRequestError with the HTTP status and a message
// naming the field.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {

struct UiRequestError : std::runtime_error {
  UiRequestError(int status, const std::string& message) : std::runtime_error(message), status(status) {}
  int status;  // HTTP status: 400 bad request, 403 refused, 404 unknown, 409 not now, 503 unavailable
};

struct UiRequestLimits {
  std::size_t max_body_bytes = 1 << 20;  // a request body (samples of many strokes: ~100 kB)
  int max_polygons = 2000;               // all classes together
  int max_vertices = 64;                 // per polygon
  int max_points = 64;                   // field correspondences
};

// The body as a JSON object; 400 when it is larger than the limit, not JSON or not an object.
nlohmann::json parseJsonBody(const std::string& body, const UiRequestLimits& limits);

// {"samples": {"blue": [[[u, v], ...], ...], ...}}: class names of docs/formats.md, polygons
// of 3..max_vertices finite vertices inside the width x height image (half a pixel margin).
ColorSamples parseSamplesRequest(const nlohmann::json& body, int width, int height,
                                 const UiRequestLimits& limits);

// {"points": [{"pixel": [u, v], "field": [x, y, z]}, ...]}: 4..max_points finite points,
// pixels inside the width x height image.
std::vector<FieldCorrespondence> parseCorrespondencesRequest(const nlohmann::json& body, int width,
                                                             int height, const UiRequestLimits& limits);

// A camera id in a path ("0".."255"); 404 otherwise.
int parseCameraId(const std::string& text);

}  // namespace soccer_vision
