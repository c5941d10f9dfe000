#include "soccer_vision/common/camera_info_yaml.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {
namespace {

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error(source + ": " + what);
}

// A {rows, cols, data: [...]} matrix of the calibration file, as a flat list.
std::vector<double> matrixData(const YAML::Node& root, const char* key, const std::string& source) {
  const YAML::Node m = root[key];
  if (!m) fail(source, std::string("missing '") + key + "'");
  const YAML::Node data = m.IsMap() ? m["data"] : m;
  if (!data || !data.IsSequence()) fail(source, std::string("'") + key + "' has no 'data' list");
  std::vector<double> out;
  for (const auto& v : data) {
    try {
      out.push_back(v.as<double>());
    } catch (const YAML::Exception&) {
      fail(source, std::string("'") + key + "' data is not a list of numbers");
    }
    if (!std::isfinite(out.back())) fail(source, std::string("'") + key + "' has a non-finite value");
  }
  return out;
}

int positiveInt(const YAML::Node& root, const char* key, const std::string& source) {
  if (!root[key]) fail(source, std::string("missing '") + key + "'");
  int v = 0;
  try {
    v = root[key].as<int>();
  } catch (const YAML::Exception&) {
    fail(source, std::string("'") + key + "' is not an integer");
  }
  if (v <= 0) fail(source, std::string("'") + key + "' must be positive");
  return v;
}

}  // namespace

CameraIntrinsics parseCameraInfoYaml(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    fail(source, std::string("invalid YAML: ") + e.what());
  }
  if (!root.IsMap()) fail(source, "not a camera calibration file (top level must be a map)");

  CameraIntrinsics k;
  k.width = positiveInt(root, "image_width", source);
  k.height = positiveInt(root, "image_height", source);
  const std::vector<double> K = matrixData(root, "camera_matrix", source);
  if (K.size() != 9) fail(source, "'camera_matrix' must have 9 values");
  if (K[0] <= 0 || K[4] <= 0) fail(source, "'camera_matrix' has no focal length (fx, fy <= 0)");
  k.fx = K[0];
  k.fy = K[4];
  k.cx = K[2];
  k.cy = K[5];

  const std::string model = root["distortion_model"] ? root["distortion_model"].as<std::string>() : "";
  const bool none = model.empty() || model == "none";
  if (!none && model != "plumb_bob" && model != "rational_polynomial") {
    fail(source, "unsupported distortion_model '" + model + "' (plumb_bob or rational_polynomial)");
  }
  std::vector<double> D;
  if (root["distortion_coefficients"]) D = matrixData(root, "distortion_coefficients", source);
  if (model == "rational_polynomial") {
    for (std::size_t i = 5; i < D.size(); ++i) {
      if (D[i] != 0) fail(source, "rational_polynomial with k4..k6 != 0 is not supported");
    }
  } else if (D.size() > 5) {
    fail(source, "plumb_bob takes at most 5 distortion coefficients, got " + std::to_string(D.size()));
  }
  if (none) {
    for (double d : D) {
      if (d != 0) fail(source, "distortion coefficients given without a distortion_model");
    }
  }
  for (std::size_t i = 0; i < 5 && i < D.size(); ++i) k.dist[i] = D[i];
  try {
    checkIntrinsics(k);
  } catch (const std::invalid_argument& e) {
    fail(source, e.what());
  }
  return k;
}

CameraIntrinsics loadCameraInfoYaml(const std::string& path) {
  return parseCameraInfoYaml(readTextFile(path), path);
}

std::string toCameraInfoYaml(const CameraIntrinsics& k, const std::string& camera_name) {
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return std::string(buf);
  };
  auto list = [&](std::initializer_list<double> v) {
    std::string out;
    for (double x : v) out += (out.empty() ? "" : ", ") + num(x);
    return "[" + out + "]";
  };
  std::string y;
  y += "image_width: " + std::to_string(k.width) + "\n";
  y += "image_height: " + std::to_string(k.height) + "\n";
  y += "camera_name: " + camera_name + "\n";
  y +=
      "camera_matrix:\n  rows: 3\n  cols: 3\n  data: " + list({k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1}) + "\n";
  y += "distortion_model: plumb_bob\n";
  y += "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: " +
       list({k.dist[0], k.dist[1], k.dist[2], k.dist[3], k.dist[4]}) + "\n";
  y += "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: " + list({1, 0, 0, 0, 1, 0, 0, 0, 1}) + "\n";
  y += "projection_matrix:\n  rows: 3\n  cols: 4\n  data: " +
       list({k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0}) + "\n";
  return y;
}

void saveCameraInfoYaml(const std::string& path, const CameraIntrinsics& k, const std::string& camera_name) {
  writeTextFile(path, toCameraInfoYaml(k, camera_name));
}

}  // namespace soccer_vision
