// calibrate_colors end to end: on make_scenario's first_frame.png + samples.yaml (the
// even_static and uneven_drift presets at 640x512) the tool writes a loadable table with its
// illumination reference, prints the statistics, writes the preview, and rejects bad
// arguments and files with exit status 2 and a message.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/segmentation/color_table.h"
#include "support/run_tool.h"

using namespace soccer_vision;

namespace {

const std::string kDir = ::testing::TempDir() + "/calibrate_colors_test";

using soccer_vision::test::ToolRun;

ToolRun run(const std::string& args) { return soccer_vision::test::runTool(CALIBRATE_COLORS_BIN, args); }

class CalibrateColors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_EQ(std::system(("rm -rf " + kDir + " && mkdir -p " + kDir + "/even " + kDir + "/uneven").c_str()),
              0);
    for (const auto& [preset, sub] :
         {std::pair<std::string, std::string>{"even_static", "even"}, {"uneven_drift", "uneven"}}) {
      const std::string cmd = std::string(MAKE_SCENARIO_BIN) + " --preset " + SOCCER_VISION_SOURCE_DIR +
                              "/config/scenarios/" + preset +
                              ".yaml --frames 1 --width 640 --height 512 --out " + kDir + "/" + sub +
                              "/s.bag > /dev/null";
      ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
  }
  static std::string image(const std::string& sub = "even") { return kDir + "/" + sub + "/first_frame.png"; }
  static std::string samples(const std::string& sub = "even") { return kDir + "/" + sub + "/samples.yaml"; }
};

TEST_F(CalibrateColors, WritesTableStatisticsAndPreview) {
  const std::string out = kDir + "/table.svct", preview = kDir + "/preview.png";
  const ToolRun r =
      run("--image " + image() + " --samples " + samples() + " --out " + out + " --preview " + preview);
  ASSERT_EQ(r.status, 0) << r.output;
  std::printf("%s", r.output.c_str());
  // Statistics: a row per class with samples, the overlap count.
  for (const char* name : {"blue", "yellow", "pink", "orange", "carpet"})
    EXPECT_NE(r.output.find(std::string("\n") + name + " "), std::string::npos) << name;
  EXPECT_NE(r.output.find("decided by Bayes"), std::string::npos);
  EXPECT_EQ(r.output.find("clipped"), std::string::npos) << "no sample is saturated here";

  const ColorTable table = ColorTable::load(out);
  const ColorSamples s = loadColorSamples(samples());
  for (const auto& [cls, polys] : s) {
    const ClassStatistics& st = table.statistics().classes[static_cast<int>(cls)];
    EXPECT_GT(st.samples, 0u) << colorClassName(cls);
    EXPECT_GT(st.valid, st.samples / 2) << colorClassName(cls);
    EXPECT_GT(st.cells_assigned, 0u) << colorClassName(cls);
    // The printed numbers are the table's.
    EXPECT_NE(r.output.find(std::to_string(st.samples)), std::string::npos);
  }
  // The illumination reference of the image: mean V per 32x32 block.
  const cv::Mat ref = table.illuminationReference();
  ASSERT_FALSE(ref.empty());
  EXPECT_EQ(ref.rows, 512 / 32);
  EXPECT_EQ(ref.cols, 640 / 32);

  // The sample pixels of the image classify as their class.
  const cv::Mat bgr = cv::imread(image(), cv::IMREAD_COLOR);
  const ClassPixels pixels = collectSamplePixels(bgr, s);
  for (const auto& [cls, px] : pixels) {
    std::size_t ok = 0;
    for (const cv::Vec3b& p : px) ok += table.classify(p[0], p[1], p[2]) == cls;
    EXPECT_GE(ok, px.size() * 9 / 10) << colorClassName(cls);
  }

  const cv::Mat pv = cv::imread(preview, cv::IMREAD_COLOR);
  ASSERT_FALSE(pv.empty());
  EXPECT_EQ(pv.cols, 2 * 640);
  EXPECT_EQ(pv.rows, 512);
}

TEST_F(CalibrateColors, SeveralImagesOneSamplesFileAndOptions) {
  const std::string out = kDir + "/two.svct";
  const ToolRun r = run("--image " + image() + " --image " + image() + " --samples " + samples() + " --out " +
                        out + " --threshold-lab 15 --threshold-h 10 --bins 60,8,8");
  ASSERT_EQ(r.status, 0) << r.output;
  const ColorTable table = ColorTable::load(out);
  EXPECT_EQ(table.params().h_bins, 60);
  EXPECT_EQ(table.params().s_bins, 8);
  EXPECT_EQ(table.params().v_bins, 8);
  EXPECT_DOUBLE_EQ(table.params().threshold_lab, 15.0);
  EXPECT_DOUBLE_EQ(table.params().threshold_h, 10.0);
  EXPECT_FALSE(table.illuminationLevels().empty());  // normalised V by default
  const ColorTable one = ColorTable::load(kDir + "/table.svct");
  // The same image twice: every sample counted twice.
  const int blue = static_cast<int>(ColorClass::Blue);
  EXPECT_EQ(table.statistics().classes[blue].samples, 2 * one.statistics().classes[blue].samples);

  // Images paired with their own samples files.
  const ToolRun pairs = run("--image " + image() + " --image " + image("uneven") + " --samples " + samples() +
                            " --samples " + samples("uneven") + " --out " + kDir + "/pairs.svct");
  ASSERT_EQ(pairs.status, 0) << pairs.output;
  EXPECT_GT(ColorTable::load(kDir + "/pairs.svct").statistics().classes[blue].samples,
            one.statistics().classes[blue].samples);
}

// Yellow tags sampled only saturated (red and green at 255, as under the brightest lamp of
// held-out seed 9043): the tool still writes the table and warns, naming yellow alone.
TEST_F(CalibrateColors, SaturatedSamplesAreWarnedOf) {
  cv::Mat bgr = cv::imread(image(), cv::IMREAD_COLOR);
  ASSERT_FALSE(bgr.empty());
  const ColorSamples s = loadColorSamples(samples());
  for (const auto& [cls, positions] : samplePixelPositions(bgr.size(), s)) {
    if (cls != ColorClass::Yellow) continue;
    for (const cv::Point& p : positions) bgr.at<cv::Vec3b>(p) = cv::Vec3b(58, 255, 255);
  }
  const std::string saturated = kDir + "/saturated.png";
  ASSERT_TRUE(cv::imwrite(saturated, bgr));
  const ToolRun r = run("--image " + saturated + " --samples " + samples() + " --out " + kDir + "/sat.svct");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::size_t at = r.output.find("warning: most sample pixels of yellow are clipped");
  EXPECT_NE(at, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("clipped", at + 60), std::string::npos) << "only yellow is named: " << r.output;
}

// --light as-captured: the paper's table (no light levels, V as captured), --v-margin kept.
TEST_F(CalibrateColors, PaperTableOfVAsCaptured) {
  const std::string out = kDir + "/paper.svct";
  const ToolRun r = run("--image " + image() + " --samples " + samples() + " --out " + out +
                        " --light as-captured --v-margin 3");
  ASSERT_EQ(r.status, 0) << r.output;
  const ColorTable table = ColorTable::load(out);
  EXPECT_TRUE(table.illuminationLevels().empty());
  EXPECT_FALSE(table.illuminationReference().empty());
  EXPECT_EQ(table.params().v_margin, 3);
  EXPECT_EQ(run("--image " + image() + " --samples " + samples() + " --out " + out + " --light dim").status,
            2);
}

TEST_F(CalibrateColors, BadArgumentsAndFilesExit2) {
  const std::string out = kDir + "/bad.svct";
  const std::string corrupt = kDir + "/corrupt.yaml";
  writeTextFile(corrupt, "pink: [[[1, 2], [3, 4]\n  - {oops\n");
  const std::string unknown = kDir + "/unknown.yaml";
  writeTextFile(unknown, "magenta:\n  - [[1, 1], [9, 1], [9, 9], [1, 9]]\n");
  const std::string outside = kDir + "/outside.yaml";
  writeTextFile(outside, "blue:\n  - [[-90, -90], [-80, -90], [-80, -80]]\n");
  const std::string not_image = kDir + "/not_an_image.png";
  writeTextFile(not_image, "garbage");

  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"--image " + image() + " --samples " + corrupt + " --out " + out, "corrupt.yaml"},
      {"--image " + image() + " --samples " + unknown + " --out " + out, "magenta"},
      {"--image " + image() + " --samples " + outside + " --out " + out, "no pixel"},
      {"--image " + kDir + "/missing.png --samples " + samples() + " --out " + out, "missing.png"},
      {"--image " + not_image + " --samples " + samples() + " --out " + out, "not_an_image.png"},
      {"--image " + image() + " --samples " + kDir + "/missing.yaml --out " + out, "missing.yaml"},
      {"--image " + image() + " --samples " + samples(), "--out"},
      {"--samples " + samples() + " --out " + out, "--image"},
      {"--image " + image() + " --image " + image() + " --samples " + samples() + " --samples " + samples() +
           " --samples " + samples() + " --out " + out,
       "samples files"},
      {"--image " + image() + " --samples " + samples() + " --out " + out + " --bins 90,16", "--bins"},
      {"--image " + image() + " --samples " + samples() + " --out " + out + " --threshold-h x",
       "--threshold-h"},
      {"--image " + image() + " --samples " + samples() + " --out " + out + " --frobnicate", "frobnicate"},
      {"--image " + image() + " --samples " + samples() + " --out " + kDir + "/no/dir/t.svct", "no/dir"},
  };
  for (const Case& c : cases) {
    const ToolRun r = run(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos)
        << "message should name '" << c.expect << "': " << r.output;
  }
  EXPECT_FALSE(std::ifstream(out).good()) << "no table is written on errors";
}

}  // namespace
