// Colour calibration as the tool, the nodelet's ~calibrate service and the benchmark do
// it: sample pixels from one or more BGR images and their sample polygons, the paper's
// colour table from them, and the illumination reference of the same images (block means
// of V and, normalised, block light levels), so that run-time adaptation measures light
// changes against the calibration (illumination_adaptation.h).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/segmentation/pixel_classifier.h"

namespace soccer_vision {

struct CalibrationImage {
  cv::Mat bgr;           // CV_8UC3
  ColorSamples samples;  // polygons in this image's pixel coordinates
  // Whether what no polygon covers is background, for the background model
  // (ColorTableParams::background_share, off by default): true for a frame sampled whole;
  // false for one on which only a few colours were added (a second frame for colours the
  // first does not show), whose unsampled markers are not background.
  bool unsampled_is_background = true;
};

// How the table files the samples' V.
enum class CalibrationLight {
  // Normalised V (the default): each sample's V scaled by the mean light level over its
  // block's level in its image, exactly as the run-time classification will scale it; the
  // table keeps the levels. Markers are then recognised in light they were not seen in.
  Normalized,
  // V as captured, the paper's table; run-time adaptation is the paper's v + k·Δv.
  AsCaptured,
};

// The colours the classifier reads from an image of this layout, as a BGR image of the
// same size: bgr8 as it is, rgb8 swapped, a Bayer mosaic as its 2x2 quads' colours (R,
// (G1 + G2 + 1) >> 1, B, as pixel_classifier.h reads them) each filling its quad. A table
// calibrated on it sees exactly the colours run-time classification looks up (a demosaic
// would interpolate other ones), on the image's own block grid.
cv::Mat classifiedColors(const cv::Mat& image, PixelLayout layout);

// Throws std::invalid_argument for no images, images of different sizes or types, or
// samples that select no pixel at all.
ColorTable calibrateColorTable(const std::vector<CalibrationImage>& images,
                               const ColorTableParams& params = {},
                               CalibrationLight light = CalibrationLight::Normalized);

// The classes of `samples` without a cell in `table`: their polygons selected no pixel, or
// the Bayes decisions gave all their cells to other classes. A table that lost a class
// cannot see that colour at all; ~calibrate refuses it.
std::vector<ColorClass> classesWithoutCells(const ColorSamples& samples, const ColorTable& table);

// The marker classes (robot markers and the ball) more than half of whose sample pixels
// are clipped in two channels (clippedTwice): their colour under less light is unknown,
// and the table will not see them where the light is dimmer (held-out seed 9043,
// rand_uneven_lamps: both yellow tags sampled at (255, 255, 58) under the brightest lamp;
// a yellow tag under a dimmer one read (214, 161, 36) and was not seen in 127 frames).
std::vector<ColorClass> classesSampledClipped(const std::vector<CalibrationImage>& images);
// The warning for them (calibrationWarnings); empty for none.
std::string clippedSamplesWarning(const std::vector<ColorClass>& classes);
// The colours `patterns` puts on robots (both teams' and every id colour) that `table` has
// no cell for: no sample covered them, or the Bayes decisions gave all their cells away. The
// table cannot see such a colour: a robot wearing it is not seen, or its marker falls to the
// nearest class and the robot is read as another id (held-out seed 9075, rand_even_static: a
// purple dot never sampled read pink, blue 1 output as blue 0 in every frame). The
// pattern's colours are the user's to check, not the table's.
std::vector<ColorClass> patternColorsWithoutCells(const PatternSet& patterns, const ColorTable& table);
// The warning for them (calibrationWarnings); empty for none.
std::string patternColorsWithoutCellsWarning(const std::vector<ColorClass>& colors,
                                             const PatternSet& patterns);
// What a calibration warns of, as calibrate_colors, evaluate and ~calibrate say it: marker
// colours sampled clipped in `images`, then, with a pattern (null: not checked), the colours
// it puts on robots that `table`, calibrated on them, has no cell for. None: empty.
std::vector<std::string> calibrationWarnings(const std::vector<CalibrationImage>& images,
                                             const ColorTable& table, const PatternSet* patterns);

// `fresh`, built from `samples` with paramsBesideKeptClasses, with every class `samples`
// has no polygon for taken from `previous` (ColorTable::withClassesFrom): a user who paints
// a few colours anew keeps the others instead of a table that no longer sees them. Throws
// std::invalid_argument when the tables' quantisation differs.
ColorTable keepUnsampledClasses(const ColorTable& fresh, const ColorTable& previous,
                                const ColorSamples& samples);

// `params` for the fresh table of keepUnsampledClasses: without what reaches beyond the
// painted classes' samples into colours no class of the fresh table was sampled on — the
// fallback of holes (fallback_sigmas) and another print's spread (print_spread). The kept
// classes have no Gaussian in it to compete, so those would give their colours to the
// painted ones, and a painted cell wins over a kept one.
ColorTableParams paramsBesideKeptClasses(ColorTableParams params);

}  // namespace soccer_vision
