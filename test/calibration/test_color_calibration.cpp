// calibrateColorTable numbers the markers sampled, the connected patches of each class's
// sample pixels, over all its images (SamplePixel::marker), so that a tag printed in another
// shade of its colour is recognised as another print of it (ColorTableParams::other_prints),
// in the first image or in a second one, painted with one polygon or a stroke of many.
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/calibration/color_calibration.h"

using namespace soccer_vision;

namespace {

// A carpet with three 12 x 6 px patches: two yellow tags in two shades (hue 66° and 40°,
// held-out seed 9039's) and an orange ball, each with a little noise.
const cv::Vec3b kGreenish(38, 205, 186), kOrangish(37, 161, 220), kOrange(8, 97, 215);

cv::Mat3b fieldImage() {
  cv::Mat3b image(48, 64, cv::Vec3b(50, 125, 55));
  auto patch = [&](int x, int y, const cv::Vec3b& c) {
    for (int v = y; v < y + 6; ++v) {
      for (int u = x; u < x + 12; ++u) {
        const int d = (u * 7 + v * 3) % 9 - 4;
        image(v, u) = cv::Vec3b(c[0] + d / 2, c[1] + d, c[2] - d);
      }
    }
  };
  patch(4, 4, kGreenish);
  patch(40, 4, kOrangish);
  patch(4, 30, kOrange);
  return image;
}

// A polygon 1 px inside the patch at (x, y).
Polygon inside(int x, int y) {
  return {{x + 0.5, y + 0.5}, {x + 10.5, y + 0.5}, {x + 10.5, y + 4.5}, {x + 0.5, y + 4.5}};
}

int yellowPixels(const ColorTable& table, const cv::Mat3b& image, int x, int y) {
  int n = 0;
  for (int v = y; v < y + 6; ++v) {
    for (int u = x; u < x + 12; ++u) {
      const cv::Vec3b p = image(v, u);
      n += table.classify(p[0], p[1], p[2]) == ColorClass::Yellow;
    }
  }
  return n;
}

}  // namespace

TEST(ColorCalibration, TwoTagsOfAColourInTwoShadesAreBothItsOwn) {
  const cv::Mat3b image = fieldImage();
  ColorSamples samples;
  samples[ColorClass::Yellow] = {inside(4, 4), inside(40, 4)};
  samples[ColorClass::Orange] = {inside(4, 30)};
  samples[ColorClass::Carpet] = {{{30, 20}, {60, 20}, {60, 44}, {30, 44}}};
  ColorTableParams off;
  off.other_prints = false;
  for (const bool second_image : {false, true}) {
    // The same tags, or the second one painted on another frame.
    std::vector<CalibrationImage> images{{image, samples}};
    if (second_image) {
      images[0].samples[ColorClass::Yellow].pop_back();
      images.push_back({image, {{ColorClass::Yellow, {inside(40, 4)}}}, false});
    }
    const ColorTable table = calibrateColorTable(images);
    EXPECT_EQ(yellowPixels(table, image, 4, 4), 72) << second_image;
    EXPECT_EQ(yellowPixels(table, image, 40, 4), 72) << second_image;
    EXPECT_EQ(yellowPixels(table, image, 4, 30), 0) << second_image;
    const ColorTable without = calibrateColorTable(images, off);
    EXPECT_LT(std::min(yellowPixels(without, image, 4, 4), yellowPixels(without, image, 40, 4)), 72)
        << second_image;
  }
  // The second tag painted as the calibration UI sends a stroke: a rectangle per segment,
  // overlapping. One marker, the same table as one polygon over it.
  ColorSamples stroke = samples;
  stroke[ColorClass::Yellow] = {inside(4, 4),
                                {{40.5, 0.5 + 4}, {44.5, 4.5}, {44.5, 8.5}, {40.5, 8.5}},
                                {{43.5, 4.5}, {48.5, 4.5}, {48.5, 8.5}, {43.5, 8.5}},
                                {{47.5, 4.5}, {50.5, 4.5}, {50.5, 8.5}, {47.5, 8.5}}};
  const ColorTable one = calibrateColorTable({{image, samples}});
  const ColorTable many = calibrateColorTable({{image, stroke}});
  const auto yellow = static_cast<int>(ColorClass::Yellow);
  EXPECT_EQ(many.statistics().classes[yellow].samples, one.statistics().classes[yellow].samples);
  EXPECT_EQ(many.statistics().classes[yellow].cells_assigned,
            one.statistics().classes[yellow].cells_assigned);
  EXPECT_EQ(yellowPixels(many, image, 40, 4), 72);
}

// Tags sampled only where they are clipped in two channels (held-out seed 9043's yellow at
// (255, 255, 58)) are named, for calibrate_colors' and ~calibrate's warning; the same tags
// sampled unclipped, a ball clipped in red alone, and white lines are not.
TEST(ColorCalibration, MarkersSampledOnlyClippedAreNamed) {
  cv::Mat3b image = fieldImage();
  image(cv::Rect(4, 4, 12, 6)).setTo(cv::Vec3b(58, 255, 255));   // yellow, R and G clipped
  image(cv::Rect(4, 30, 12, 6)).setTo(cv::Vec3b(14, 161, 255));  // orange, R clipped
  image(cv::Rect(24, 20, 12, 6)).setTo(cv::Vec3b(255, 255, 255));
  ColorSamples samples;
  samples[ColorClass::Yellow] = {inside(4, 4)};
  samples[ColorClass::Orange] = {inside(4, 30)};
  samples[ColorClass::Line] = {inside(24, 20)};
  const std::vector<ColorClass> clipped = classesSampledClipped({{image, samples}});
  EXPECT_EQ(clipped, std::vector<ColorClass>{ColorClass::Yellow});
  EXPECT_NE(clippedSamplesWarning(clipped).find("yellow"), std::string::npos);
  EXPECT_EQ(clippedSamplesWarning({}), "");

  // Sampled also on an unclipped tag (the other shade's patch): half clipped is not most.
  samples[ColorClass::Yellow].push_back(inside(40, 4));
  EXPECT_TRUE(classesSampledClipped({{image, samples}}).empty());
}

// The colours a pattern puts on robots that the table has no cell for are named with the ids
// wearing them (held-out seed 9075: purple unsampled, blue 1 read as blue 0): here blue,
// yellow, pink and sky blue are sampled, on separate patches.
TEST(ColorCalibration, PatternColorsTheTableLacksAreNamed) {
  cv::Mat3b image = fieldImage();
  image(cv::Rect(4, 4, 12, 6)).setTo(cv::Vec3b(200, 80, 30));     // blue
  image(cv::Rect(40, 4, 12, 6)).setTo(cv::Vec3b(30, 220, 230));   // yellow
  image(cv::Rect(4, 30, 12, 6)).setTo(cv::Vec3b(180, 80, 240));   // pink
  image(cv::Rect(40, 30, 12, 6)).setTo(cv::Vec3b(230, 200, 60));  // sky blue
  ColorSamples samples;
  samples[ColorClass::Blue] = {inside(4, 4)};
  samples[ColorClass::Yellow] = {inside(40, 4)};
  samples[ColorClass::Pink] = {inside(4, 30)};
  samples[ColorClass::SkyBlue] = {inside(40, 30)};
  samples[ColorClass::Carpet] = {{{20.5, 14.5}, {34.5, 14.5}, {34.5, 24.5}, {20.5, 24.5}}};
  const ColorTable table = calibrateColorTable({{image, samples}});
  const PatternSet two_tag = PatternSet::twoTag();
  const std::vector<ColorClass> missing = patternColorsWithoutCells(two_tag, table);
  EXPECT_EQ(missing, (std::vector<ColorClass>{ColorClass::Purple, ColorClass::Green, ColorClass::Red}));
  const std::string warning = patternColorsWithoutCellsWarning(missing, two_tag);
  EXPECT_NE(warning.find("purple, green, red"), std::string::npos) << warning;
  EXPECT_NE(warning.find("(ids 1, 3, 4)"), std::string::npos) << warning;
  EXPECT_EQ(patternColorsWithoutCellsWarning({}, two_tag), "");
  // What calibrate_colors, evaluate and ~calibrate say: that warning (nothing is clipped
  // here), or nothing without a pattern.
  EXPECT_EQ(calibrationWarnings({{image, samples}}, table, &two_tag), std::vector<std::string>{warning});
  EXPECT_TRUE(calibrationWarnings({{image, samples}}, table, nullptr).empty());

  // The SSL pattern wears pink and green beside the team colours; team_only only those.
  EXPECT_EQ(patternColorsWithoutCells(PatternSet::ssl(), table), std::vector<ColorClass>{ColorClass::Green});
  EXPECT_TRUE(patternColorsWithoutCells(PatternSet::teamOnly(), table).empty());
  samples.erase(ColorClass::Yellow);
  EXPECT_EQ(patternColorsWithoutCells(PatternSet::teamOnly(), calibrateColorTable({{image, samples}})),
            std::vector<ColorClass>{ColorClass::Yellow});
}
