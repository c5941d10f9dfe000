// The segmentation stage of the pipeline (paper §III-A/B, Fig. 3) as one object: per
// frame, illumination offsets per block, then regions of the marker classes found by the
// RegionExtractor over a FrameClassifier — in the whole frame or in search windows.
// Everything it returns is in image pixel coordinates, whatever the encoding.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/segmentation/ball_streak_table.h"
#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/segmentation/illumination_adaptation.h"
#include "soccer_vision/segmentation/pixel_classifier.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

struct SegmentationParams {
  // Illumination adaptation (illumination_adaptation.h), in the table's mode. 0 disables
  // it (normalised tables: the light as calibrated); otherwise the paper's k for tables of
  // V as captured, while normalised tables measure every frame's block light levels.
  double illumination_k = 0.3;
  int illumination_sample_step = 8;  // read every n-th row/column of a block for its mean V / level (16 of
                                     // 1024: the mean of a noisy carpet to 0.4 levels)
  int max_illumination_offset = 64;  // |k·Δv| clamp, 8-bit V units (paper's mode)
  double sharpen = 0.0;              // Laplacian sharpening of V (paper §IV): v -= sharpen * ∇²v; 0 = off
  // In label pixels of a 1280-px-wide label image (kRegionParamsWidth) of a camera over
  // half the field. Narrower label images (lower resolutions, Bayer mosaics: one label per
  // 2x2 quad) use labelParams(regions, width), so that the same settings keep markers of
  // the same size.
  RegionParams regions;
  // In the ball's window (Segmenter::process' streak_windows), orange regions come from the
  // streak table (ball_streak_table.h): a kicked ball blurred into a streak of ball and
  // carpet is found there although the colour table's orange does not reach its mixture.
  // false = off.
  bool ball_streaks = true;
  // A streak-table region is refused, and the colour table's orange kept in its place, when
  // less than this share of a ring around it reads as the floor (floor_surround.h): a ball
  // lies on the carpet, a print on a robot's top. A ball against a wall or a robot keeps
  // about half; 0 = off.
  double ball_streak_floor_share = 0.3;
};

// Region parameters are given for a label image this wide; narrower ones scale them.
constexpr int kRegionParamsWidth = 1280;
// Below this share of kRegionParamsWidth the opening kernel is halved.
constexpr double kKeepKernelRatio = 0.75;
// Region parameters for a label image `label_width` px wide (r = width / 1280, at most 1):
// kernel k / 2 below r = 0.75 (3 -> 1, i.e. off: a 3x3 opening erases a 30 mm tag of
// ~4 px, and 2 loses its edge pixels; without the opening, regions must then hold two
// adjacent pixels of their class: require_pair, a checkerboard scan), areas x r² (at
// least 1), tiles x r (at least 8).
// Unchanged at 1280 px and wider.
RegionParams labelParams(const RegionParams& params, int label_width);
// Bayer quads of a 1280x1024 mosaic: labelParams(params, 640).
RegionParams quadLabelParams(const RegionParams& image_pixels);

struct SegmentationTimings {
  double illumination_ms = 0, classification_ms = 0, morphology_ms = 0, regions_ms = 0, total_ms = 0;
};

struct SegmentationResult {
  std::vector<Region> regions;  // image pixel coordinates (Bayer: quad centres mapped back)
  bool global_search = true;
  std::vector<cv::Rect> windows;  // image pixels, as used (clipped to the image)
  std::array<std::uint32_t, kNumColorClasses> cap_hits{};
  // Bayer colour fringes dropped per class (mosaic_fringes.h).
  std::array<std::uint32_t, kNumColorClasses> fringes{};
  bool illumination_size_mismatch = false;  // reference made for another image size
  BlockOffsets offsets;                     // the illumination adjustment the frame was classified with
  std::uint32_t grid_points = 0;            // label pixels looked up by the grid scan
  std::uint32_t classified_pixels = 0;      // label pixels classified around the hits
  std::uint32_t streak_windows = 0;         // streak windows searched with the streak table
  std::uint32_t streak_regions = 0;         // orange regions of the streak windows from the streak table
  std::uint32_t streak_refused = 0;         // streak-table regions refused: not on the floor
  SegmentationTimings timings;
};

// The shared, immutable part: colour table + its fast lookup + illumination reference.
// Built once per table (costly: fills the lookup), then shared by pointer and swapped
// atomically when a new table is loaded or calibrated.
struct SegmentationModel {
  std::shared_ptr<const PixelClassifier> classifier;
  // The ball's streak table (ballStreakTable); null when the table has no ball or carpet.
  std::shared_ptr<const PixelClassifier> streak_classifier;
  IlluminationAdaptation illumination;

  static std::shared_ptr<const SegmentationModel> fromTable(std::shared_ptr<const ColorTable> table,
                                                            const BallStreakParams& streak = {});
};

class Segmenter {
 public:
  explicit Segmenter(const SegmentationParams& params = {});
  void setParams(const SegmentationParams& params);
  const SegmentationParams& params() const { return params_; }

  // One frame. `windows` in image pixels; empty = global search. `streak_windows`: where
  // the ball is expected (SearchPlan::ball_streak_rects; image pixels, whether the frame is
  // searched whole or not), in which the orange regions are the streak table's
  // (SegmentationParams::ball_streaks). Throws std::invalid_argument for an image whose
  // type does not fit `layout`.
  void process(const SegmentationModel& model, const cv::Mat& image, PixelLayout layout,
               const std::vector<cv::Rect>& windows, SegmentationResult& out,
               const std::vector<cv::Rect>& streak_windows = {});

 private:
  SegmentationParams params_;
  // A region extractor of labelParams for the label width it was last made for.
  struct SizedExtractor {
    RegionExtractor extractor;
    int width = -1;  // -1: not made yet
  };
  // `e`, remade for `classes` when the label width differs from the one it was made for.
  RegionExtractor& extractorFor(SizedExtractor& e, int label_width, ClassMask classes);
  SizedExtractor extractor_;         // the marker classes of params_.regions
  SizedExtractor streak_extractor_;  // orange only, for the streak windows
  // Orange regions of the streak windows from the streak table, replacing the colour
  // table's there.
  // `colors`: the frame under the colour table, which tells the floor around a streak.
  void findBallStreaks(const SegmentationModel& model, const FrameClassifier& colors, const cv::Mat& image,
                       PixelLayout layout, const std::vector<cv::Rect>& streak_windows,
                       SegmentationResult& out);
};

// Whether the stripes searched for a lost ball (SearchPlan::lost_ball_streak_rects) take
// the ball's streak table on this layout: not on Bayer quads, whose white lines read as
// cyan and yellow fringes that the streak table takes for a ball blurred with the carpet
// (docs/segmentation.md#the-balls-streak).
bool searchesLostBallStreaks(PixelLayout layout);
// The streak windows of a frame: the ball's, and the lost ball's stripes where the layout
// takes them (searchesLostBallStreaks).
std::vector<cv::Rect> streakWindows(PixelLayout layout, const std::vector<cv::Rect>& ball_streak,
                                    const std::vector<cv::Rect>& lost_ball_streak);

// Labels of every pixel (label resolution) with the same illumination offsets and
// sharpening as Segmenter::process, e.g. for the debug image and accuracy tests.
cv::Mat classifyAll(const SegmentationModel& model, const cv::Mat& image, PixelLayout layout,
                    const SegmentationParams& params = {});
// Colour-coded BGR picture of a label image (each class in its nominal colour, None black).
cv::Mat colorizeLabels(const cv::Mat& labels);

}  // namespace soccer_vision
