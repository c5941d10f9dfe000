// The ball's streak table (ball_streak_table.h): the mixtures of the ball with the carpet
// from min_ball_share on are orange, mixed in the encoded values or in linear light; the
// carpet, the other marker colours and mostly-carpet mixtures are not.
#include <cmath>

#include <gtest/gtest.h>

#include "ball_and_carpet_samples.h"
#include "soccer_vision/segmentation/ball_streak_table.h"
#include "soccer_vision/segmentation/segmenter.h"

using namespace soccer_vision;

namespace {

const cv::Vec3d kBall = test::kSampledBall, kCarpet = test::kSampledCarpet;

ColorClass classify(const ColorTable& table, const cv::Vec3d& bgr) {
  return table.classify(cv::saturate_cast<std::uint8_t>(bgr[0]), cv::saturate_cast<std::uint8_t>(bgr[1]),
                        cv::saturate_cast<std::uint8_t>(bgr[2]));
}

// share x ball + (1 - share) x carpet in linear light (gamma 2.2), encoded again.
cv::Vec3d linearMix(double share) {
  cv::Vec3d out;
  for (int i = 0; i < 3; ++i) {
    const double l = share * std::pow(kBall[i] / 255, 2.2) + (1 - share) * std::pow(kCarpet[i] / 255, 2.2);
    out[i] = 255 * std::pow(l, 1 / 2.2);
  }
  return out;
}

}  // namespace

TEST(BallStreakTable, HoldsTheStreaksMixturesTheColourTableLeavesOut) {
  const ColorTable table = ColorTable::buildFromSamplePixels(test::ballAndCarpetSamples());
  const auto streak = ballStreakTable(table);
  ASSERT_TRUE(streak);
  // A 12 m/s streak's middle: 60 % ball, in either mixing.
  for (const cv::Vec3d& mix : {0.6 * kBall + 0.4 * kCarpet, linearMix(0.6), 0.4 * kBall + 0.6 * kCarpet}) {
    EXPECT_NE(classify(table, mix), ColorClass::Orange);
    EXPECT_EQ(classify(*streak, mix), ColorClass::Orange);
  }
  EXPECT_EQ(classify(*streak, kBall), ColorClass::Orange);
  // Mostly carpet, the carpet, and the other markers' colours are not the ball's.
  EXPECT_EQ(classify(*streak, 0.15 * kBall + 0.85 * kCarpet), ColorClass::None);
  EXPECT_EQ(classify(*streak, kCarpet), ColorClass::None);
  EXPECT_EQ(classify(*streak, cv::Vec3d(32, 170, 240)), ColorClass::None);  // yellow
  EXPECT_EQ(classify(*streak, cv::Vec3d(38, 40, 230)), ColorClass::None);   // red
  // Every cell of the table's orange is the streak table's too, and it holds nothing else.
  for (std::size_t i = 0; i < table.cells().size(); ++i) {
    if (table.cells()[i] == ColorClass::Orange) {
      EXPECT_EQ(streak->cells()[i], ColorClass::Orange) << i;
    }
    EXPECT_TRUE(streak->cells()[i] == ColorClass::Orange || streak->cells()[i] == ColorClass::None) << i;
  }
}

TEST(BallStreakTable, NeedsTheBallAndTheCarpetAndSaneParameters) {
  ClassSamplePixels samples = test::ballAndCarpetSamples();
  samples.erase(ColorClass::Carpet);
  EXPECT_FALSE(ballStreakTable(ColorTable::buildFromSamplePixels(samples)));
  samples = test::ballAndCarpetSamples();
  samples.erase(ColorClass::Orange);
  EXPECT_FALSE(ballStreakTable(ColorTable::buildFromSamplePixels(samples)));
  const ColorTable table = ColorTable::buildFromSamplePixels(test::ballAndCarpetSamples());
  for (const BallStreakParams& bad : {BallStreakParams{0, 0.12, 2.2}, BallStreakParams{1, 0.12, 2.2},
                                      BallStreakParams{0.3, 0, 2.2}, BallStreakParams{0.3, NAN, 2.2},
                                      BallStreakParams{0.3, 0.12, 0.5}, BallStreakParams{NAN, 0.12, 2.2}}) {
    EXPECT_THROW(ballStreakTable(table, bad), std::invalid_argument);
  }
}

// A lost ball's stripes take the streak table on colour images, not on Bayer quads: there a
// white line reads as cyan and yellow fringes, which it took for a ball blurred with the
// carpet (spent seeds 9029 and 9031 of rand_bayer: ball precision 51 % and 68 %).
TEST(BallStreakTable, SearchesALostBallOnColourImagesOnly) {
  EXPECT_TRUE(searchesLostBallStreaks(PixelLayout::Bgr));
  EXPECT_TRUE(searchesLostBallStreaks(PixelLayout::Rgb));
  for (const PixelLayout bayer :
       {PixelLayout::BayerRggb, PixelLayout::BayerBggr, PixelLayout::BayerGbrg, PixelLayout::BayerGrbg})
    EXPECT_FALSE(searchesLostBallStreaks(bayer));
  const std::vector<cv::Rect> ball = {{10, 10, 40, 40}}, lost = {{0, 200, 1280, 80}};
  EXPECT_EQ(streakWindows(PixelLayout::Bgr, ball, lost), (std::vector<cv::Rect>{ball[0], lost[0]}));
  EXPECT_EQ(streakWindows(PixelLayout::BayerRggb, ball, lost), ball);
}
