// The exchange files other tools read and write (docs/formats.md):
//  - per-frame results / ground truth as JSON Lines (field frame, SI units),
//  - colour samples (YAML: class name -> polygons in pixel coordinates),
//  - field correspondences (YAML: points: [{pixel: [u, v], field: [x, y, z]}]).
// Readers throw std::runtime_error naming the file and line/key on bad input.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/color_class.h"

namespace soccer_vision {

struct RobotRecord {
  Team team = Team::Blue;
  int id = 0;
  double x = 0, y = 0, theta = 0;
  std::optional<bool> visible;       // ground truth only
  std::optional<double> confidence;  // results only
};

struct BallRecord {
  double x = 0, y = 0;
  std::optional<bool> visible;
  std::optional<double> confidence;
};

struct FrameRecord {
  double stamp = 0;  // capture stamp, s
  std::vector<RobotRecord> robots;
  std::vector<BallRecord> balls;
};

// One JSON object on one line (no trailing newline).
std::string toJsonLine(const FrameRecord& frame);
FrameRecord parseJsonLine(const std::string& line);
void writeJsonLines(const std::string& path, const std::vector<FrameRecord>& frames);
std::vector<FrameRecord> readJsonLines(const std::string& path);

using Polygon = std::vector<Eigen::Vector2d>;
// Class -> polygons (pixel coordinates of one image). Unknown class names are errors.
using ColorSamples = std::map<ColorClass, std::vector<Polygon>>;

// Limits of colour samples (docs/robustness.md). A clicked polygon has a handful of
// vertices; the limits bound the work of one calibration (rows x vertices) and keep every
// coordinate far inside the range of an int.
constexpr std::size_t kMaxPolygonVertices = 10000;
constexpr std::size_t kMaxSamplePolygons = 1000;    // all classes together
constexpr std::size_t kMaxSampleVertices = 100000;  // all polygons together
constexpr double kMaxSampleCoordinate = 1e6;        // |u|, |v| in pixels
// Throws std::invalid_argument naming the class, the polygon (0-based) and the vertex for a
// polygon with fewer than 3 or more than kMaxPolygonVertices vertices, a NaN or infinite
// coordinate or one beyond kMaxSampleCoordinate, no area (all vertices on one line), or
// more than kMaxSamplePolygons polygons or kMaxSampleVertices vertices in all. Every reader and user of
// samples calls it.
void checkColorSamples(const ColorSamples& samples);
std::string toYaml(const ColorSamples& samples);
ColorSamples parseColorSamples(const std::string& yaml_text, const std::string& source_name);
ColorSamples loadColorSamples(const std::string& path);
// The names of the classes `samples` has polygons for, in class order: "blue, yellow".
std::string sampledClassNames(const ColorSamples& samples);

struct FieldCorrespondence {
  Eigen::Vector2d pixel;  // raw (distorted) image
  Eigen::Vector3d field;  // metres
};
// Far more than anyone clicks; the pose solver compares every pair.
constexpr std::size_t kMaxFieldCorrespondences = 10000;
std::string toYaml(const std::vector<FieldCorrespondence>& points);
std::vector<FieldCorrespondence> parseFieldCorrespondences(const std::string& yaml_text,
                                                           const std::string& source_name);
std::vector<FieldCorrespondence> loadFieldCorrespondences(const std::string& path);

// Whole file as a string; throws with the path when it cannot be read.
std::string readTextFile(const std::string& path);
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace soccer_vision
