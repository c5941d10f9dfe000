// Online self-calibration (paper §III-B, taken to the colour table; docs/segmentation.md):
// while the system runs, the segmentation model is refined from what the system is sure of.
//
//  * Marker cells. The interior pixels of the regions identification confirmed (markers of
//    robots identified with high confidence, FrameIdentifier::identify) vote for the table
//    cell they are looked up in: (H, S) of the pixel and V under this frame's illumination
//    adjustment, exactly as the classification reads it. A cell the calibrated table leaves
//    to no class is given to class c once, over the decaying votes, it has min_votes of c,
//    at least `purity` of all marker votes in it, not one background vote, and its centre
//    lies within learn_sigmas of c's calibrated H, S, V Gaussian.
//  * Background votes: label pixels on a sparse grid away from every region (carpet, lines,
//    whatever lies beyond the field). They veto a cell; a learned cell that gets one is given
//    back at the next update.
//  * Light (normalised tables). The expected carpet level per block, the centre of the band
//    in which blockLightLevels reads the carpet, follows the shape of the carpet's light
//    (expectedLightLevels of a frame, the global change divided out): after a lamp went out,
//    its blocks are read again instead of being filled from their neighbours.
//
// Guards: votes halve at every update (old light is forgotten); updates come at most once
// per update_period of capture stamps, each changing at most max_cells_per_update cells and
// the expected levels by at most level_rate; max_learned_cells in all. The calibrated model
// (the base) is never changed: reset() returns to it.
//
// Deterministic: the result depends on the frames and their stamps only. Not thread-safe:
// one caller at a time (the pipeline's loop, the nodelet's learning thread).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/segmentation/region_extractor.h"
#include "soccer_vision/segmentation/segmenter.h"

namespace soccer_vision {

struct OnlineCalibrationParams {
  bool enabled = false;
  // Share of a marker's radius whose pixels vote: the rim mixes with the robot's top.
  double interior = 0.6;
  // Capture-stamp seconds between model updates (each one rebuilds the lookup: ~0.1 s).
  double update_period = 1.0;
  int min_votes = 8;          // decayed votes of one class a cell needs
  double purity = 0.95;       // that class's share of the cell's marker votes
  double learn_sigmas = 4.0;  // cells beyond this of the class's calibrated H, S, V Gaussian stay out
  int max_cells_per_update = 32;
  int max_learned_cells = 1024;
  int background_stride = 16;  // label pixels between background samples (both axes)
  // Per update, the expected carpet levels move at most this share of the way to the
  // frame's light shape; 0 = the light is not learned.
  double level_rate = 0.5;

  // Throws std::invalid_argument naming the parameter for values out of range.
  void validate() const;
};

// What the learning saw and did; counters since construction or reset().
struct OnlineCalibrationStatus {
  std::uint64_t frames = 0;            // frames observed
  std::uint64_t markers = 0;           // confirmed marker regions read
  std::uint64_t marker_votes = 0;      // their interior pixels
  std::uint64_t background_votes = 0;  // background pixels read
  std::uint64_t updates = 0;           // updates made (one per update_period)
  std::uint64_t models = 0;            // of them, updates that changed the model
  std::uint64_t cells_added = 0, cells_removed = 0;
  std::array<std::uint32_t, kNumColorClasses> learned_cells{};  // per class, now
  std::uint32_t vetoed_cells = 0;      // cells with enough marker votes but a background vote (last update)
  std::uint32_t outside_envelope = 0;  // cells with enough votes but beyond learn_sigmas (last update)
  double level_deviation = 0;          // max |expected / calibrated - 1| of the blocks' light, now
  double last_update_stamp = 0;
  std::uint32_t learnedTotal() const;
};

class OnlineCalibration {
 public:
  // `base`: the calibrated model (never changed). Throws std::invalid_argument for bad
  // params or a null base.
  OnlineCalibration(std::shared_ptr<const SegmentationModel> base, const OnlineCalibrationParams& params);

  const OnlineCalibrationParams& params() const { return params_; }
  // New parameters; the votes and the learned state are kept. Throws like the constructor.
  void setParams(const OnlineCalibrationParams& params);

  // One segmented frame: the image, its layout and the BlockOffsets it was segmented with
  // (SegmentationResult::offsets), all its regions (image pixels, SegmentationResult) and
  // the indices of those identification confirmed. Throws std::invalid_argument for an
  // image that does not fit the layout or offsets of another block grid.
  void observe(const cv::Mat& image, PixelLayout layout, const BlockOffsets& offsets, double sharpen,
               const std::vector<Region>& regions, const std::vector<int>& confirmed, double stamp);
  // The model to use from now on when an update is due at `stamp` (update_period after the
  // last one) and it changed something; nullptr otherwise. A stamp before the last update
  // (time jumped back) starts the period again.
  std::shared_ptr<const SegmentationModel> update(double stamp);

  // The learned model (the base until the first update).
  const std::shared_ptr<const SegmentationModel>& model() const { return model_; }
  const std::shared_ptr<const SegmentationModel>& base() const { return base_; }
  const OnlineCalibrationStatus& status() const { return status_; }
  // Back to the base model; votes, learned cells, light and counters cleared.
  void reset();

 private:
  struct Votes {
    std::array<float, kNumColorClasses> marker{};  // [ColorClass::None] unused
    float background = 0;
  };
  void voteMarker(const FrameClassifier& frame, const Region& region, PixelLayout layout);
  void voteBackground(const FrameClassifier& frame, const std::vector<Region>& regions, PixelLayout layout);
  std::size_t cellOf(const cv::Vec3b& bgr, int adapted_v) const;
  bool insideEnvelope(std::size_t cell, ColorClass c) const;
  bool updateCells();
  bool updateLight();

  OnlineCalibrationParams params_;
  std::shared_ptr<const SegmentationModel> base_, model_;
  std::vector<Votes> votes_;         // per table cell
  std::vector<ColorClass> learned_;  // per table cell: the class learned (None: none)
  cv::Mat expected_;                 // CV_32FC1 expected carpet levels (empty: the base's)
  cv::Mat light_shape_;              // the last observed frame's light shape, for the next update
  bool have_stamp_ = false;
  OnlineCalibrationStatus status_;
};

}  // namespace soccer_vision
