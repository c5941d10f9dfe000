// The fast path of the colour table (PixelClassifier / FrameClassifier) against the
// table's definition, ColorTable::classify: every 24-bit colour at several V offsets,
// every camera layout, block offsets, the grid scan, sharpening; and the paper's block-wise
// illumination adaptation (§III-B).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/segmentation/illumination_adaptation.h"
#include "soccer_vision/segmentation/pixel_classifier.h"
#include "soccer_vision/segmentation/simd_kernels.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"

using namespace soccer_vision;

namespace {

// A table calibrated on rendered frames of both cameras (markers, ball and background
// classes), and a later frame of camera 0 with robots and ball elsewhere.
struct World {
  ScenarioConfig scenario;
  FieldGeometry field;
  PatternSet patterns = patternSetByName(scenario.pattern);
  GameSimulator sim{scenario, field, patterns.maxRobotsPerTeam()};
  std::shared_ptr<const ColorTable> table;
  std::unique_ptr<PixelClassifier> classifier;
  cv::Mat calibration;  // camera 0, bgr8
  cv::Mat frame;        // camera 0, bgr8, one second later

  World() {
    ClassPixels samples;
    for (int camera = 0; camera < 2; ++camera) {
      FieldRenderer renderer(CameraModel::defaultCamera(field, camera, scenario.width, scenario.height),
                             field, patterns, scenario);
      RenderedFrame rendered;
      renderer.render(sim.state(), 0, rendered);
      for (auto& [c, px] : collectSamplePixels(
               rendered.image, calibrationSamples(sim.state(), renderer.camera(), field, patterns))) {
        samples[c].insert(samples[c].end(), px.begin(), px.end());
      }
      if (camera == 0) calibration = rendered.image;
    }
    // The paper's body (no generalisation): the adaptation tests below measure what the
    // offsets recover, which a generalised table would partly absorb.
    ColorTableParams paper;
    paper.generalize_sigmas = 0;
    table = std::make_shared<const ColorTable>(ColorTable::build(samples, paper));
    const auto start = std::chrono::steady_clock::now();
    classifier = std::make_unique<PixelClassifier>(table);
    std::printf("[ classifier ] lookup built in %.1f ms\n",
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    for (int i = 0; i < 60; ++i) sim.step(1.0 / scenario.fps);
    FieldRenderer renderer(CameraModel::defaultCamera(field, 0, scenario.width, scenario.height), field,
                           patterns, scenario);
    RenderedFrame rendered;
    renderer.render(sim.state(), 60, rendered);
    frame = rendered.image;
  }
};

const World& world() {
  static const World w;
  return w;
}

// Adjustments per 32x32 block that differ between neighbouring blocks: every third block a
// gain from 0.9 to 1.1 (the normalised mode), the others offsets of both signs.
BlockOffsets patternedOffsets(cv::Size image_size) {
  BlockOffsets o;
  o.offsets.create((image_size.height + 31) / 32, (image_size.width + 31) / 32, CV_16SC1);
  o.gains.create(o.offsets.size(), CV_16UC1);
  for (int i = 0; i < o.offsets.rows; ++i) {
    for (int j = 0; j < o.offsets.cols; ++j) {
      const bool gain = (i + j) % 3 == 0;
      o.offsets.at<std::int16_t>(i, j) = static_cast<std::int16_t>(gain ? 0 : (i * 7 + j * 13) % 81 - 40);
      o.gains.at<std::uint16_t>(i, j) =
          static_cast<std::uint16_t>(gain ? 230 + (i * 11 + j * 5) % 53 : ColorTable::kUnitGain);
    }
  }
  return o;
}

int offsetOf(const BlockOffsets& o, int image_x, int image_y) {
  return o.offsets.empty() ? 0 : o.offsets.at<std::int16_t>(image_y / 32, image_x / 32);
}
int gainOf(const BlockOffsets& o, int image_x, int image_y) {
  return o.gains.empty() ? ColorTable::kUnitGain : o.gains.at<std::uint16_t>(image_y / 32, image_x / 32);
}

cv::Mat classifyAll(const FrameClassifier& fc) {
  cv::Mat labels;
  fc.classify({0, 0, fc.labelSize().width, fc.labelSize().height}, labels);
  return labels;
}

// Mosaic whose quads hold (B, G1, G2, R) at the positions `pattern` ("rggb", ...) names,
// taken from a BGR image twice the size: G1 and G2 from different pixels, so their mean is
// often a half that the rounding rule decides.
cv::Mat mosaic(const cv::Mat3b& bgr, const std::string& pattern) {
  cv::Mat1b raw(bgr.rows / 2 * 2, bgr.cols / 2 * 2);
  for (int y = 0; y < raw.rows; y += 2) {
    for (int x = 0; x < raw.cols; x += 2) {
      const cv::Vec3b& p = bgr(y, x);
      const cv::Vec3b& q = bgr(y + 1, x + 1);
      bool first_green = true;
      for (int k = 0; k < 4; ++k) {
        std::uint8_t value = 0;
        switch (pattern[k]) {
          case 'b':
            value = p[0];
            break;
          case 'r':
            value = p[2];
            break;
          default:
            value = first_green ? p[1] : q[1];
            first_green = false;
        }
        raw(y + k / 2, x + k % 2) = value;
      }
    }
  }
  return raw;
}

// Quad colours by the documented rule: R, (G1 + G2 + 1) >> 1, B.
cv::Vec3b quadColor(const cv::Mat1b& raw, const std::string& pattern, int x, int y) {
  int b = 0, r = 0, g_sum = 0;
  for (int k = 0; k < 4; ++k) {
    const int v = raw(2 * y + k / 2, 2 * x + k % 2);
    if (pattern[k] == 'b')
      b = v;
    else if (pattern[k] == 'r')
      r = v;
    else
      g_sum += v;
  }
  return cv::Vec3b(static_cast<std::uint8_t>(b), static_cast<std::uint8_t>((g_sum + 1) >> 1),
                   static_cast<std::uint8_t>(r));
}

}  // namespace

// ------------------------------------------------------------------ the lookup itself

TEST(PixelClassifier, EqualsTheColorTableOnEveryColourAndOffset) {
  const World& w = world();
  const ColorTable& table = *w.table;
  int classes_present = 0;
  for (int c = 1; c < kNumColorClasses; ++c)
    classes_present += table.statistics().classes[c].cells_assigned > 0;
  ASSERT_EQ(classes_present, kNumColorClasses - 1) << "the table should hold every class";

  // ColorTable::classify is bgrToHsv followed by classifyHsv(h, s, adjustedV(v, offset,
  // gain)): the HSV conversion is done once per colour, the definition's lookup once per
  // adjustment. The unit gain is the paper's v + offset.
  const int offsets[] = {-300, -40, -7, 0, 5, 33, 300};
  const int gains[] = {32, 181, 300, 2047};
  std::int64_t mismatches = 0, non_none = 0;
  for (int b = 0; b < 256; ++b) {
    for (int g = 0; g < 256; ++g) {
      for (int r = 0; r < 256; ++r) {
        const auto bb = static_cast<std::uint8_t>(b), gg = static_cast<std::uint8_t>(g),
                   rr = static_cast<std::uint8_t>(r);
        const Hsv hsv = bgrToHsv(bb, gg, rr);
        for (int offset : offsets) {
          const ColorClass expected = table.classifyHsv(hsv.h, hsv.s, hsv.v + offset);
          const ColorClass got = w.classifier->classify(bb, gg, rr, offset);
          non_none += expected != ColorClass::None;
          if (got != expected && ++mismatches <= 5) {
            ADD_FAILURE() << "(" << b << ", " << g << ", " << r << ") offset " << offset << ": "
                          << colorClassName(got) << " instead of " << colorClassName(expected);
          }
        }
        for (int gain : gains) {
          const int offset = gain % 2 ? -7 : 0;  // odd gains with an offset too
          const ColorClass expected =
              table.classifyHsv(hsv.h, hsv.s, std::floor((hsv.v * gain + 128) / 256) + offset);
          const ColorClass got = w.classifier->classify(bb, gg, rr, offset, gain);
          if (got != expected && ++mismatches <= 5) {
            ADD_FAILURE() << "(" << b << ", " << g << ", " << r << ") gain " << gain << " offset " << offset
                          << ": " << colorClassName(got) << " instead of " << colorClassName(expected);
          }
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(non_none, 100000);
  // Spot checks through the public definition itself.
  for (const auto& [b, g, r] :
       {std::tuple{201, 80, 20}, {30, 220, 240}, {45, 120, 50}, {0, 0, 0}, {255, 255, 255}}) {
    for (int offset : offsets) {
      const auto bb = static_cast<std::uint8_t>(b), gg = static_cast<std::uint8_t>(g),
                 rr = static_cast<std::uint8_t>(r);
      EXPECT_EQ(w.classifier->classify(bb, gg, rr, offset), table.classify(bb, gg, rr, offset));
      for (int gain : gains) {
        EXPECT_EQ(w.classifier->classify(bb, gg, rr, offset, gain), table.classify(bb, gg, rr, offset, gain));
      }
    }
  }
}

TEST(PixelClassifier, EncodingsLayoutsAndClassMasks) {
  EXPECT_EQ(pixelLayoutForEncoding("bgr8"), PixelLayout::Bgr);
  EXPECT_EQ(pixelLayoutForEncoding("rgb8"), PixelLayout::Rgb);
  EXPECT_EQ(pixelLayoutForEncoding("bayer_rggb8"), PixelLayout::BayerRggb);
  EXPECT_EQ(pixelLayoutForEncoding("bayer_bggr8"), PixelLayout::BayerBggr);
  EXPECT_EQ(pixelLayoutForEncoding("bayer_gbrg8"), PixelLayout::BayerGbrg);
  EXPECT_EQ(pixelLayoutForEncoding("bayer_grbg8"), PixelLayout::BayerGrbg);
  for (const PixelLayout layout : {PixelLayout::Bgr, PixelLayout::Rgb, PixelLayout::BayerRggb,
                                   PixelLayout::BayerBggr, PixelLayout::BayerGbrg, PixelLayout::BayerGrbg})
    EXPECT_EQ(pixelLayoutForEncoding(encodingForPixelLayout(layout)), layout);
  EXPECT_STREQ(encodingForPixelLayout(PixelLayout::BayerGbrg), "bayer_gbrg8");
  for (const char* unsupported : {"mono8", "mono16", "bgr16", "rgb16", "bgra8", "rgba8", "16UC1", "8UC3",
                                  "yuv422", "uyvy", "bayer_rggb16", "BGR8", ""}) {
    EXPECT_EQ(pixelLayoutForEncoding(unsupported), std::nullopt) << unsupported;
  }
  EXPECT_FALSE(isBayer(PixelLayout::Bgr));
  EXPECT_FALSE(isBayer(PixelLayout::Rgb));
  EXPECT_TRUE(isBayer(PixelLayout::BayerGrbg));
  EXPECT_EQ(labelSize({1280, 1024}, PixelLayout::Rgb), cv::Size(1280, 1024));
  EXPECT_EQ(labelSize({1280, 1024}, PixelLayout::BayerRggb), cv::Size(640, 512));

  ClassMask markers = 0;
  for (ColorClass c : {ColorClass::Blue, ColorClass::Yellow, ColorClass::Pink, ColorClass::Purple,
                       ColorClass::SkyBlue, ColorClass::Green, ColorClass::Red, ColorClass::Orange}) {
    markers |= classBit(c);
  }
  EXPECT_EQ(markerClassMask(), markers);

  const PixelClassifier& pc = *world().classifier;
  const cv::Mat3b bgr(4, 4, cv::Vec3b(1, 2, 3));
  EXPECT_THROW(FrameClassifier(pc, cv::Mat1b(4, 4), PixelLayout::Bgr, {}), std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, cv::Mat1b(4, 5), PixelLayout::BayerRggb, {}), std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, cv::Mat1b(3, 4), PixelLayout::BayerRggb, {}), std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, bgr, PixelLayout::BayerRggb, {}), std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, cv::Mat(4, 4, CV_16UC3), PixelLayout::Bgr, {}), std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, bgr, PixelLayout::Bgr, BlockOffsets{cv::Mat1s(2, 1), {}}),
               std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, bgr, PixelLayout::Bgr, BlockOffsets{cv::Mat1i(1, 1), {}}),
               std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, bgr, PixelLayout::Bgr, BlockOffsets{{}, cv::Mat1s(1, 1)}),
               std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, bgr, PixelLayout::Bgr, BlockOffsets{{}, cv::Mat_<std::uint16_t>(2, 1)}),
               std::invalid_argument);
  EXPECT_THROW(FrameClassifier(pc, bgr, PixelLayout::Bgr, {}, -0.5), std::invalid_argument);
  const FrameClassifier fc(pc, bgr, PixelLayout::Bgr, {});
  cv::Mat out;
  EXPECT_THROW(fc.classify({2, 2, 3, 1}, out), std::invalid_argument);
  std::vector<cv::Point> hits;
  EXPECT_THROW(fc.scanGrid({0, 0, 4, 4}, 0, markers, hits), std::invalid_argument);
  EXPECT_THROW(fc.scanGrid({-1, 0, 4, 4}, 1, markers, hits), std::invalid_argument);
}

// ------------------------------------------------------------------ frames

// Every pixel of a rendered frame, cut to partial blocks (and not continuous in memory),
// with different offsets per block: label = table.classify(b, g, r, offsets(y/32, x/32)).
TEST(FrameClassifier, BgrFrameUsesTheOffsetOfEachPixelsBlock) {
  const World& w = world();
  const cv::Mat3b image = w.frame(cv::Rect(7, 5, 1001, 707));
  ASSERT_FALSE(image.isContinuous());
  const BlockOffsets offsets = patternedOffsets(image.size());
  ASSERT_EQ(offsets.offsets.size(), cv::Size(32, 23));
  const FrameClassifier fc(*w.classifier, image, PixelLayout::Bgr, offsets);
  ASSERT_EQ(fc.labelSize(), image.size());
  const cv::Mat1b labels = classifyAll(fc);
  std::int64_t wrong = 0, markers = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b& p = image(y, x);
      const int offset = offsetOf(offsets, x, y), gain = gainOf(offsets, x, y);
      const ColorClass expected = w.table->classify(p[0], p[1], p[2], offset, gain);
      wrong += labels(y, x) != static_cast<std::uint8_t>(expected);
      markers += isMarkerColor(expected);
      if ((x * 31 + y * 17) % 997 == 0) {
        ASSERT_EQ(fc.adaptedV(x, y), ColorTable::adjustedV(std::max({p[0], p[1], p[2]}), offset, gain));
        ASSERT_EQ(fc.colorAt(x, y), p);
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(markers, 100) << "the frame should show markers";

  // A rect written into a view of a larger matrix leaves the rest alone.
  cv::Mat1b canvas(100, 100, std::uint8_t{255});
  cv::Mat view = canvas(cv::Rect(10, 20, 64, 48));
  fc.classify({300, 200, 64, 48}, view);
  EXPECT_EQ(cv::countNonZero(canvas != 255), cv::countNonZero(view != 255));
  EXPECT_EQ(cv::norm(view, labels(cv::Rect(300, 200, 64, 48)), cv::NORM_INF), 0.0);
}

TEST(FrameClassifier, RgbAndEveryBayerLayoutClassifyTheirQuadColours) {
  const World& w = world();
  const cv::Mat3b bgr = w.frame(cv::Rect(0, 0, 1280, 1000));  // 1000 rows: partial blocks
  const BlockOffsets offsets = patternedOffsets(bgr.size());

  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  const FrameClassifier from_rgb(*w.classifier, rgb, PixelLayout::Rgb, offsets);
  const FrameClassifier from_bgr(*w.classifier, bgr, PixelLayout::Bgr, offsets);
  EXPECT_EQ(cv::norm(classifyAll(from_rgb), classifyAll(from_bgr), cv::NORM_INF), 0.0);
  EXPECT_EQ(from_rgb.colorAt(100, 200), bgr(200, 100));

  const std::pair<std::string, PixelLayout> layouts[] = {{"rggb", PixelLayout::BayerRggb},
                                                         {"bggr", PixelLayout::BayerBggr},
                                                         {"gbrg", PixelLayout::BayerGbrg},
                                                         {"grbg", PixelLayout::BayerGrbg}};
  for (const auto& [pattern, layout] : layouts) {
    const cv::Mat1b raw = mosaic(bgr, pattern);
    ASSERT_EQ(pixelLayoutForEncoding("bayer_" + pattern + "8"), layout);
    const FrameClassifier fc(*w.classifier, raw, layout, offsets);
    ASSERT_EQ(fc.labelSize(), cv::Size(640, 500));
    const cv::Mat1b labels = classifyAll(fc);
    std::int64_t wrong = 0, odd_green_sums = 0, markers = 0;
    for (int y = 0; y < labels.rows; ++y) {
      for (int x = 0; x < labels.cols; ++x) {
        const cv::Vec3b q = quadColor(raw, pattern, x, y);
        const ColorClass expected = w.table->classify(q[0], q[1], q[2], offsetOf(offsets, 2 * x, 2 * y),
                                                      gainOf(offsets, 2 * x, 2 * y));
        wrong += labels(y, x) != static_cast<std::uint8_t>(expected);
        markers += isMarkerColor(expected);
        odd_green_sums += (bgr(2 * y, 2 * x)[1] + bgr(2 * y + 1, 2 * x + 1)[1]) % 2;
        if ((x + y) % 101 == 0) {
          ASSERT_EQ(fc.colorAt(x, y), q) << pattern;
        }
      }
    }
    EXPECT_EQ(wrong, 0) << pattern;
    EXPECT_GT(markers, 20) << pattern;
    EXPECT_GT(odd_green_sums, labels.total() / 4) << "the rounding of the green mean is exercised";
  }
}

// The layouts read the renderer's own mosaics the way it wrote them: the quad colours of a
// Bayer rendering are the BGR rendering's channels at the pattern's positions.
TEST(FrameClassifier, BayerLayoutsMatchTheRenderersEncodings) {
  const World& w = world();
  ScenarioConfig scenario = w.scenario;
  scenario.sensor.noise_sigma = 0;  // same picture whatever the output format
  scenario.width = 640;             // small frames: the test is about the encodings
  scenario.height = 512;
  const CameraModel camera = CameraModel::defaultCamera(w.field, 0, scenario.width, scenario.height);
  RenderedFrame bgr;
  FieldRenderer(camera, w.field, w.patterns, scenario).render(w.sim.state(), 0, bgr);
  for (const std::string pattern : {"rggb", "bggr", "gbrg", "grbg"}) {
    scenario.sensor.bayer = pattern;
    FieldRenderer renderer(camera, w.field, w.patterns, scenario);
    RenderedFrame raw;
    renderer.render(w.sim.state(), 0, raw);
    const std::optional<PixelLayout> layout = pixelLayoutForEncoding(raw.encoding);
    ASSERT_TRUE(layout) << raw.encoding;
    const FrameClassifier fc(*w.classifier, raw.image, *layout, {});
    int wrong = 0;
    for (int y = 0; y < fc.labelSize().height; y += 7) {
      for (int x = 0; x < fc.labelSize().width; x += 5) {
        int b = 0, r = 0, g = 0;
        for (int k = 0; k < 4; ++k) {
          const cv::Vec3b& p = bgr.image.at<cv::Vec3b>(2 * y + k / 2, 2 * x + k % 2);
          if (pattern[k] == 'b')
            b = p[0];
          else if (pattern[k] == 'r')
            r = p[2];
          else
            g += p[1];
        }
        wrong += fc.colorAt(x, y) != cv::Vec3b(static_cast<std::uint8_t>(b),
                                               static_cast<std::uint8_t>((g + 1) >> 1),
                                               static_cast<std::uint8_t>(r));
      }
    }
    EXPECT_EQ(wrong, 0) << raw.encoding;
  }
}

// Both kernels of the scan (the AVX-512 one where the CPU has it, and the portable one).
class ScanKernels : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override { detail::allowSimdKernels(GetParam()); }
  void TearDown() override { detail::allowSimdKernels(true); }
};

TEST_P(ScanKernels, ScanGridReturnsExactlyTheStridePointsOfTheWantedClasses) {
  const World& w = world();
  const cv::Mat bgr = w.frame;
  const cv::Mat raw = mosaic(bgr, "grbg");
  const BlockOffsets offsets = patternedOffsets(bgr.size());
  for (const auto& [image, layout] : {std::pair{bgr, PixelLayout::Bgr}, {raw, PixelLayout::BayerGrbg}}) {
    const FrameClassifier fc(*w.classifier, image, layout, offsets);
    const cv::Mat1b labels = classifyAll(fc);
    const cv::Size size = fc.labelSize();
    for (const cv::Rect rect : {cv::Rect(0, 0, size.width, size.height), cv::Rect(101, 58, 333, 250),
                                cv::Rect(size.width - 41, size.height - 40, 41, 40), cv::Rect(5, 5, 0, 9)}) {
      for (int stride : {1, 2, 3, 4}) {
        for (ClassMask classes : {markerClassMask(), classBit(ColorClass::Green),
                                  classBit(ColorClass::Carpet) | classBit(ColorClass::Blue),
                                  classBit(ColorClass::None), ClassMask(0)}) {
          std::vector<cv::Point> expected;
          for (int y = rect.y; y < rect.y + rect.height; ++y) {
            for (int x = rect.x; x < rect.x + rect.width; ++x) {
              if (x % stride == 0 && y % stride == 0 && (classes & (ClassMask(1) << labels(y, x)))) {
                expected.emplace_back(x, y);
              }
            }
          }
          std::vector<cv::Point> hits = {cv::Point(-1, -1)};  // appended to, not replaced
          fc.scanGrid(rect, stride, classes, hits);
          ASSERT_EQ(hits.front(), cv::Point(-1, -1));
          hits.erase(hits.begin());
          EXPECT_EQ(hits, expected) << "stride " << stride << " classes " << classes << " rect " << rect;
          if (classes == markerClassMask() && rect.width == size.width && stride == 3) {
            EXPECT_GT(hits.size(), 5u);
          }
        }
      }
    }
  }
}

// The scan's V' at the limits of its 16-bit arithmetic: gains from 2^15 on (block rows of
// those take the 32-bit path) and up to 2^15 - 1, offsets that overflow 16 bits when added.
TEST_P(ScanKernels, ScanGridEqualsTheLabelsWithExtremeGainsAndOffsets) {
  const World& w = world();
  BlockOffsets offsets = patternedOffsets(w.frame.size());
  for (int i = 0; i < offsets.gains.rows; ++i) {
    for (int j = 0; j < offsets.gains.cols; ++j) {
      const int kind = (i + 2 * j) % 5;
      if (kind == 1) offsets.gains.at<std::uint16_t>(i, j) = i % 2 ? 40000 : 32767;
      if (kind == 2) offsets.offsets.at<std::int16_t>(i, j) = 32767;
      if (kind == 3) offsets.offsets.at<std::int16_t>(i, j) = -32768;
      if (kind == 4) offsets.gains.at<std::uint16_t>(i, j) = 1;
    }
  }
  std::size_t found = 0;
  for (const auto& [image, layout] :
       {std::pair{w.frame, PixelLayout::Bgr}, {mosaic(w.frame, "rggb"), PixelLayout::BayerRggb}}) {
    const FrameClassifier fc(*w.classifier, image, layout, offsets);
    const cv::Mat1b labels = classifyAll(fc);
    const cv::Size size = fc.labelSize();
    for (int stride : {1, 2, 3}) {
      std::vector<cv::Point> expected, hits;
      for (int y = 0; y < size.height; y += stride) {
        for (int x = 0; x < size.width; x += stride) {
          if (markerClassMask() & (ClassMask(1) << labels(y, x))) expected.emplace_back(x, y);
        }
      }
      fc.scanGrid(cv::Rect(cv::Point(0, 0), size), stride, markerClassMask(), hits);
      EXPECT_EQ(hits, expected) << "stride " << stride << " layout " << static_cast<int>(layout);
      found += expected.size();
    }
  }
  EXPECT_GT(found, 50u);  // markers remain to be found under these blocks
}

// classify's kernels against classifyPixel (the scalar definition) on rects of every
// width up to 40 and odd offsets (tails of the 16-pixel steps, rects across blocks).
TEST_P(ScanKernels, ClassifyEqualsClassifyPixelOnEveryRect) {
  const World& w = world();
  const BlockOffsets offsets = patternedOffsets(w.frame.size());
  for (const auto& [image, layout] :
       {std::pair{w.frame, PixelLayout::Bgr}, {mosaic(w.frame, "bggr"), PixelLayout::BayerBggr}}) {
    const FrameClassifier fc(*w.classifier, image, layout, offsets);
    const cv::Size size = fc.labelSize();
    for (ClassMask keep :
         {~ClassMask(0), markerClassMask(), classBit(ColorClass::Blue) | classBit(ColorClass::Yellow)}) {
      int wrong = 0, marked = 0;
      for (int width = 1; width <= 40; ++width) {
        const cv::Rect rect((width * 37) % (size.width - 40), (width * 23) % (size.height - 8), width, 8);
        cv::Mat labels;
        fc.classify(rect, labels, keep);
        for (int y = 0; y < rect.height; ++y) {
          for (int x = 0; x < rect.width; ++x) {
            const std::uint8_t expected = fc.classifyPixel(rect.x + x, rect.y + y, keep);
            wrong += labels.at<std::uint8_t>(y, x) != expected;
          }
        }
      }
      cv::Mat whole;
      fc.classify(cv::Rect(0, 0, size.width, size.height), whole, keep);
      for (int y = 0; y < size.height; y += 2) {
        for (int x = 0; x < size.width; ++x) {
          const std::uint8_t expected = fc.classifyPixel(x, y, keep);
          wrong += whole.at<std::uint8_t>(y, x) != expected;
          marked += expected != 0;
        }
      }
      EXPECT_EQ(wrong, 0) << static_cast<int>(layout) << " keep " << keep;
      EXPECT_GT(marked, 20);  // the kept classes are there to be found
    }
  }
}

INSTANTIATE_TEST_SUITE_P(FrameClassifier, ScanKernels, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& info) {
                           return info.param ? "Simd" : "Portable";
                         });

// classify(rect, out, keep) equals classify(rect, out) with the other classes set to None,
// for every layout, with and without sharpening.
TEST(FrameClassifier, KeepingClassesEqualsTheFullLabelsMasked) {
  const World& w = world();
  const cv::Mat bgr = w.frame;
  const cv::Mat raw = mosaic(bgr, "rggb");
  const BlockOffsets offsets = patternedOffsets(bgr.size());
  std::int64_t kept_pixels = 0;
  for (const auto& [image, layout] : {std::pair{bgr, PixelLayout::Bgr}, {raw, PixelLayout::BayerRggb}}) {
    for (double sharpen : {0.0, 0.5}) {
      const FrameClassifier fc(*w.classifier, image, layout, offsets, sharpen);
      const cv::Size size = fc.labelSize();
      const cv::Rect rect(0, 0, size.width, size.height);
      cv::Mat all;
      fc.classify(rect, all);
      for (ClassMask keep :
           {markerClassMask(), classBit(ColorClass::Carpet) | classBit(ColorClass::Pink), ClassMask(0)}) {
        cv::Mat kept;
        fc.classify(rect, kept, keep);
        cv::Mat1b expected = all.clone();
        for (auto& label : expected) {
          if (!(keep & (ClassMask(1) << label))) label = 0;
        }
        ASSERT_EQ(cv::countNonZero(kept != expected), 0) << "keep " << keep << " sharpen " << sharpen;
        kept_pixels += cv::countNonZero(kept);
      }
    }
  }
  EXPECT_GT(kept_pixels, 10000);  // the comparison saw real labels, not only None
}

// V_s = clamp(V - lround(sharpen * L), 0, 255) with the 4-neighbour Laplacian L of V over
// the whole label image (border replicated), then the block gain and offset; H and S unchanged.
TEST(FrameClassifier, SharpeningReplacesVByTheSharpenedV) {
  const World& w = world();
  const cv::Mat3b bgr = w.frame(cv::Rect(0, 0, 640, 480));
  const cv::Mat raw = mosaic(bgr, "rggb");
  const BlockOffsets offsets = patternedOffsets(bgr.size());
  const double sharpen = 0.7;
  for (const auto& [image, layout, pattern] : {std::tuple{cv::Mat(bgr), PixelLayout::Bgr, std::string()},
                                               {raw, PixelLayout::BayerRggb, std::string("rggb")}}) {
    const FrameClassifier fc(*w.classifier, image, layout, offsets, sharpen);
    const cv::Size size = fc.labelSize();
    auto color = [&](int x, int y) {
      return layout == PixelLayout::Bgr ? bgr(y, x) : quadColor(raw, pattern, x, y);
    };
    auto v = [&](int x, int y) {
      const cv::Vec3b c = color(std::clamp(x, 0, size.width - 1), std::clamp(y, 0, size.height - 1));
      return static_cast<int>(std::max({c[0], c[1], c[2]}));
    };
    const int scale = layout == PixelLayout::Bgr ? 1 : 2;
    cv::Mat1b expected(size);
    std::int64_t changed_v = 0, changed_class = 0;
    for (int y = 0; y < size.height; ++y) {
      for (int x = 0; x < size.width; ++x) {
        const int laplacian = v(x - 1, y) + v(x + 1, y) + v(x, y - 1) + v(x, y + 1) - 4 * v(x, y);
        const int sharpened =
            std::clamp(static_cast<int>(v(x, y) - std::lround(sharpen * laplacian)), 0, 255);
        const int offset = offsetOf(offsets, scale * x, scale * y),
                  gain = gainOf(offsets, scale * x, scale * y);
        const cv::Vec3b c = color(x, y);
        const Hsv hsv = bgrToHsv(c[0], c[1], c[2]);
        const ColorClass sharp =
            w.table->classifyHsv(hsv.h, hsv.s, ColorTable::adjustedV(sharpened, offset, gain));
        expected(y, x) = static_cast<std::uint8_t>(sharp);
        changed_v += sharpened != v(x, y);
        changed_class += sharp != w.table->classify(c[0], c[1], c[2], offset, gain);
        if ((x * 13 + y * 7) % 211 == 0) {
          ASSERT_EQ(fc.adaptedV(x, y), ColorTable::adjustedV(sharpened, offset, gain));
        }
      }
    }
    EXPECT_EQ(cv::norm(classifyAll(fc), expected, cv::NORM_INF), 0.0) << static_cast<int>(layout);
    EXPECT_GT(changed_v, 1000);
    EXPECT_GT(changed_class, 10) << "sharpening should matter somewhere";
    // A rect inside reads its neighbours from the image, not from the rect's border.
    cv::Mat part;
    const cv::Rect rect(50, 40, 100, 60);
    fc.classify(rect, part);
    EXPECT_EQ(cv::norm(part, expected(rect), cv::NORM_INF), 0.0);
    std::vector<cv::Point> hits, expected_hits;
    fc.scanGrid(rect, 2, markerClassMask(), hits);
    for (int y = rect.y; y < rect.br().y; y += 2) {
      for (int x = rect.x; x < rect.br().x; x += 2) {
        if (isMarkerColor(static_cast<ColorClass>(expected(y, x)))) expected_hits.emplace_back(x, y);
      }
    }
    EXPECT_EQ(hits, expected_hits);
  }
}

// ------------------------------------------------------------------ illumination

TEST(Illumination, BlockMeanVEqualsADirectComputation) {
  const World& w = world();
  const cv::Mat3b bgr = w.frame(cv::Rect(3, 1, 1000, 706));  // partial blocks on both sides
  const cv::Mat raw = mosaic(bgr, "bggr");
  for (const auto& [image, layout, pattern] : {std::tuple{cv::Mat(bgr), PixelLayout::Bgr, std::string()},
                                               {raw, PixelLayout::BayerBggr, std::string("bggr")}}) {
    const int block = isBayer(layout) ? 16 : 32;
    const cv::Size size = labelSize(image.size(), layout);
    for (int step : {1, 3, 4}) {
      const cv::Mat means = blockMeanV(image, layout, step);
      ASSERT_EQ(means.type(), CV_32FC1);
      ASSERT_EQ(means.size(), cv::Size(32, 23));
      double worst = 0;
      for (int by = 0; by < means.rows; ++by) {
        for (int bx = 0; bx < means.cols; ++bx) {
          double sum = 0;
          int n = 0;
          for (int y = by * block; y < std::min((by + 1) * block, size.height); y += step) {
            for (int x = bx * block; x < std::min((bx + 1) * block, size.width); x += step) {
              const cv::Vec3b c = pattern.empty() ? bgr(y, x) : quadColor(raw, pattern, x, y);
              sum += std::max({c[0], c[1], c[2]});
              ++n;
            }
          }
          worst = std::max(worst, std::abs(sum / n - means.at<float>(by, bx)));
        }
      }
      EXPECT_LT(worst, 1e-4) << "step " << step;
    }
  }
  EXPECT_THROW(blockMeanV(bgr, PixelLayout::Bgr, 0), std::invalid_argument);
  EXPECT_THROW(blockMeanV(raw, PixelLayout::Bgr), std::invalid_argument);
}

TEST(Illumination, OffsetsAreTheRoundedClampedScaledDifference) {
  const cv::Mat3b image(64, 96, cv::Vec3b(10, 100, 20));  // 2 x 3 blocks of V 100
  image(cv::Rect(32, 0, 32, 32)).setTo(cv::Vec3b(0, 0, 200));
  const cv::Mat1f reference = (cv::Mat1f(2, 3) << 100, 90, 150, 300, 0, 102.5);
  const IlluminationAdaptation adaptation(reference);
  ASSERT_TRUE(adaptation.hasReference());
  bool mismatch = true;
  const BlockOffsets o = adaptation.offsets(image, PixelLayout::Bgr, 0.5, 1, 64, &mismatch);
  EXPECT_FALSE(mismatch);
  ASSERT_EQ(o.offsets.type(), CV_16SC1);
  // 0.5 * (ref - now): 0, -55, 25; 100 -> 64 (clamped), -50, 1.25 -> 1.
  const cv::Mat1s expected = (cv::Mat1s(2, 3) << 0, -55, 25, 64, -50, 1);
  EXPECT_EQ(cv::norm(o.offsets, expected, cv::NORM_INF), 0.0);
  // Half away from zero: 0.5 * (102.5 - 100) = 1.25 -> 1; 0.5 * (103 - 100) = 1.5 -> 2.
  const IlluminationAdaptation half(cv::Mat1f(2, 3, 97.0f));
  EXPECT_EQ(half.offsets(image, PixelLayout::Bgr, 0.5, 1).offsets.at<std::int16_t>(1, 0), -2);

  EXPECT_TRUE(adaptation.offsets(image, PixelLayout::Bgr, 0.0, 1).offsets.empty());  // k = 0: all zero
  EXPECT_TRUE(IlluminationAdaptation().offsets(image, PixelLayout::Bgr, 0.3, 1).offsets.empty());
  const BlockOffsets other = adaptation.offsets(cv::Mat3b(64, 128), PixelLayout::Bgr, 0.3, 1, 64, &mismatch);
  EXPECT_TRUE(mismatch);
  EXPECT_TRUE(other.offsets.empty());
  EXPECT_THROW(adaptation.offsets(image, PixelLayout::Bgr, 0.3, 1, -1), std::invalid_argument);

  // The reference from calibration images is the mean of their block means.
  const cv::Mat3b darker = image * 0.5;
  const IlluminationAdaptation both = IlluminationAdaptation::fromImages({image, darker}, PixelLayout::Bgr);
  EXPECT_NEAR(both.reference().at<float>(0, 0), 75.0, 1e-4);
  EXPECT_NEAR(both.reference().at<float>(0, 1), 150.0, 1e-4);
  EXPECT_THROW(IlluminationAdaptation::fromImages({}, PixelLayout::Bgr), std::invalid_argument);
  EXPECT_THROW(IlluminationAdaptation::fromImages({image, cv::Mat3b(64, 64)}, PixelLayout::Bgr),
               std::invalid_argument);
}

// The calibration frame darkened to 90 %: adaptation brings its labels back towards the
// labels of the frame the table was calibrated on. The offset of a block follows its mean
// V, i.e. the carpet's, so it restores only part of a bright marker's (multiplicative)
// loss: at 90 % about 28 % of the marker pixels keep their class without adaptation,
// ~38 % with k = 0.3 and ~69 % with k = 1.
TEST(Illumination, AdaptationRecoversADarkenedFrame) {
  const World& w = world();
  const cv::Mat bright = w.calibration;
  const cv::Mat dark = bright * 0.9;
  const IlluminationAdaptation adaptation(
      IlluminationAdaptation::fromImages({bright}, PixelLayout::Bgr).reference());
  const cv::Mat1b reference = classifyAll(FrameClassifier(*w.classifier, bright, PixelLayout::Bgr, {}));
  auto agreement = [&](double k) {
    const BlockOffsets offsets = adaptation.offsets(dark, PixelLayout::Bgr, k, 4);
    const cv::Mat1b labels = classifyAll(FrameClassifier(*w.classifier, dark, PixelLayout::Bgr, offsets));
    std::int64_t markers = 0, same_markers = 0, same = 0;
    for (int y = 0; y < labels.rows; ++y) {
      for (int x = 0; x < labels.cols; ++x) {
        same += labels(y, x) == reference(y, x);
        if (isMarkerColor(static_cast<ColorClass>(reference(y, x)))) {
          ++markers;
          same_markers += labels(y, x) == reference(y, x);
        }
      }
    }
    std::printf("  k %.1f: labels as in the bright frame %.2f %%, marker pixels %.2f %% of %ld\n", k,
                100.0 * same / labels.total(), 100.0 * same_markers / markers, static_cast<long>(markers));
    return std::pair{static_cast<double>(same) / labels.total(), static_cast<double>(same_markers) / markers};
  };
  const auto [all_off, markers_off] = agreement(0.0);
  const auto [all_03, markers_03] = agreement(0.3);
  const auto [all_1, markers_1] = agreement(1.0);
  EXPECT_GT(markers_03, markers_off + 0.05);
  EXPECT_GT(markers_1, markers_off + 0.3);
  EXPECT_GE(all_03, all_off);
  EXPECT_GE(all_1, all_03);
}

// Search windows: only the blocks they meet are measured. The paper's offsets there are
// exactly the full frame's (each block is on its own) and zero elsewhere; normalised gains
// there follow the same light, measured from fewer blocks (global change and fill level
// from the windows alone): within 2 % of the full frame's (measured: equal, as the carpet
// band of each block hardly moves with the global estimate).
TEST(Illumination, WindowsMeasureOnlyTheBlocksTheyMeet) {
  const World& w = world();
  const cv::Mat dark = w.frame * 0.8;
  const std::vector<cv::Rect> windows = {{100, 90, 200, 200}, {-50, 900, 200, 200}, {1000, 400, 64, 31}};
  const cv::Mat1b selected = blocksMeeting(dark, PixelLayout::Bgr, windows);
  ASSERT_EQ(selected.size(), cv::Size(40, 32));
  // Blocks (x, y) 3..9 x 2..9, 0..4 x 28..31 (clipped), 31..33 x 12..13.
  EXPECT_EQ(cv::countNonZero(selected), 7 * 8 + 5 * 4 + 3 * 2);
  EXPECT_TRUE(selected(2, 3) && selected(9, 9) && !selected(10, 9) && !selected(2, 10) && !selected(1, 3));

  const IlluminationAdaptation paper(
      IlluminationAdaptation::fromImages({w.calibration}, PixelLayout::Bgr).reference());
  const BlockOffsets full = paper.offsets(dark, PixelLayout::Bgr, 0.3, 4);
  const BlockOffsets windowed = paper.offsets(dark, PixelLayout::Bgr, 0.3, 4, 64, nullptr, &windows);
  ASSERT_EQ(windowed.offsets.size(), full.offsets.size());
  for (int y = 0; y < selected.rows; ++y) {
    for (int x = 0; x < selected.cols; ++x) {
      const int expected = selected(y, x) ? full.offsets.at<std::int16_t>(y, x) : 0;
      ASSERT_EQ(windowed.offsets.at<std::int16_t>(y, x), expected) << "block " << x << ", " << y;
    }
  }

  const IlluminationAdaptation normalised =
      IlluminationAdaptation::fromImages({w.calibration}, PixelLayout::Bgr);
  const BlockOffsets full_gains = normalised.offsets(dark, PixelLayout::Bgr, 0.3, 4);
  const BlockOffsets windowed_gains =
      normalised.offsets(dark, PixelLayout::Bgr, 0.3, 4, 64, nullptr, &windows);
  double worst = 0;
  for (int y = 0; y < selected.rows; ++y) {
    for (int x = 0; x < selected.cols; ++x) {
      if (!selected(y, x)) continue;
      const double a = full_gains.gains.at<std::uint16_t>(y, x),
                   b = windowed_gains.gains.at<std::uint16_t>(y, x);
      worst = std::max(worst, std::abs(a - b) / a);
    }
  }
  std::printf("  windowed gains within %.3f %% of the full frame's\n", 100 * worst);
  EXPECT_LT(worst, 0.02);
  // The darkening is seen: the gains are 1 / 0.8 of those of the frame as rendered.
  const BlockOffsets undarkened =
      normalised.offsets(w.frame, PixelLayout::Bgr, 0.3, 4, 64, nullptr, &windows);
  EXPECT_NEAR(double(windowed_gains.gains.at<std::uint16_t>(5, 5)) / undarkened.gains.at<std::uint16_t>(5, 5),
              1.25, 0.03);
}
