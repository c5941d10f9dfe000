// A recalibration of a few colours keeps the others (keepUnsampledClasses, as ~calibrate
// and the calibration UI merge): painted classes come from the new samples alone, every
// other class keeps its cells of the current table where the new table claims nothing.
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/common/color_space.h"

using namespace soccer_vision;

namespace {

cv::Vec3b hsv(double h, double s, double v) {
  const auto bgr = hsvToBgr(Hsv{h, s, v});
  return {bgr[0], bgr[1], bgr[2]};
}

// A few dozen pixels around one colour given as HSV (hue in degrees).
std::vector<cv::Vec3b> around(double h, double s, double v) {
  std::vector<cv::Vec3b> out;
  for (int dv = -6; dv <= 6; dv += 3) {
    for (double dh = -3; dh <= 3; dh += 1.5) out.push_back(hsv(h + dh, s, v + dv));
  }
  return out;
}

// Polygons stand for "this class was painted": keepUnsampledClasses reads only the keys.
ColorSamples painted(std::initializer_list<ColorClass> classes) {
  ColorSamples samples;
  for (const ColorClass c : classes) samples[c] = {Polygon{{0, 0}, {4, 0}, {4, 4}}};
  return samples;
}

ColorClass classify(const ColorTable& t, const cv::Vec3b& bgr) { return t.classify(bgr[0], bgr[1], bgr[2]); }

}  // namespace

TEST(KeepUnsampledClasses, RecalibratingOneColourKeepsTheOthers) {
  const cv::Vec3b blue = hsv(220, 0.8, 150), yellow = hsv(55, 0.8, 200);
  const cv::Vec3b old_pink = hsv(330, 0.5, 200), new_pink = hsv(315, 0.6, 170);
  const cv::Vec3b carpet = hsv(120, 0.5, 90);
  const ColorTable previous = ColorTable::build({{ColorClass::Blue, around(220, 0.8, 150)},
                                                 {ColorClass::Yellow, around(55, 0.8, 200)},
                                                 {ColorClass::Pink, around(330, 0.5, 200)}});
  const ColorTable fresh = ColorTable::build(
      {{ColorClass::Pink, around(315, 0.6, 170)}, {ColorClass::Carpet, around(120, 0.5, 90)}},
      paramsBesideKeptClasses(ColorTableParams()));
  ASSERT_EQ(classify(fresh, blue), ColorClass::None);  // the strokes alone forget blue

  const ColorTable merged =
      keepUnsampledClasses(fresh, previous, painted({ColorClass::Pink, ColorClass::Carpet}));
  EXPECT_EQ(classify(merged, blue), ColorClass::Blue);
  EXPECT_EQ(classify(merged, yellow), ColorClass::Yellow);
  EXPECT_EQ(classify(merged, new_pink), ColorClass::Pink);
  EXPECT_EQ(classify(merged, carpet), ColorClass::Carpet);
  // Pink was painted: its old cells that the new samples did not reach are not kept.
  EXPECT_EQ(classify(fresh, old_pink), classify(merged, old_pink));

  // Every cell is counted once, and kept classes bring their statistics.
  std::size_t assigned = 0;
  for (const auto& c : merged.statistics().classes) assigned += c.cells_assigned;
  EXPECT_EQ(assigned, merged.cells().size());
  const auto& kept_blue = merged.statistics().classes[static_cast<int>(ColorClass::Blue)];
  EXPECT_EQ(kept_blue.samples, previous.statistics().classes[static_cast<int>(ColorClass::Blue)].samples);
  EXPECT_EQ(kept_blue.cells_assigned,
            previous.statistics().classes[static_cast<int>(ColorClass::Blue)].cells_assigned);
  // Nothing the new table claims is overwritten.
  for (std::size_t i = 0; i < merged.cells().size(); ++i) {
    if (fresh.cells()[i] != ColorClass::None) {
      ASSERT_EQ(merged.cells()[i], fresh.cells()[i]) << "cell " << i;
    }
  }
}

TEST(KeepUnsampledClasses, TablesOfAnotherQuantisationAreRefused) {
  ColorTableParams coarse;
  coarse.h_bins = 45;
  const ColorTable previous = ColorTable::build({{ColorClass::Blue, around(220, 0.8, 150)}}, coarse);
  const ColorTable fresh = ColorTable::build({{ColorClass::Pink, around(315, 0.6, 170)}});
  EXPECT_THROW(keepUnsampledClasses(fresh, previous, painted({ColorClass::Pink})), std::invalid_argument);
}
