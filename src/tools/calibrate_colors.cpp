// calibrate_colors: the paper's offline colour calibration (§III-A) as a command. From one
// or more calibration images and the sample polygons on each, builds the colour
// table (mean Lab / mean H per class, valid samples, HSV bodies, naive Bayes on overlaps),
// attaches the illumination reference of the images (mean V and carpet light level per
// 32x32 block) and writes a versioned .svct file for the Segmentation nodelet (parameter
// color_table). By default the table files normalised V (illumination_adaptation.h);
// --light as-captured builds the paper's table of V as captured (adaptation v + k·Δv).
//
//   rosrun soccer_vision calibrate_colors --image A.png [--image B.png ...]
//       --samples samples.yaml [--samples ...] --out table.svct [--preview preview.png]
//       [--threshold-lab X] [--threshold-h DEG] [--bins H,S,V] [--v-margin N]
//       [--generalize SIGMAS] [--spread L,AB] [--fallback SIGMAS] [--fallback-guard SIGMAS]
//       [--light normalized|as-captured] [--patterns NAME|FILE]
//
// Images and samples files pair up in order; a single samples file applies to every image.
// All images must have the same size (the illumination reference is per block).
// Prints per class: sample and valid counts, mean Lab, mean H, thresholds, cells claimed by
// its HSV body and held after the Bayes decisions, and the number of cells claimed by more
// than one class. --preview writes the first image beside its colour-coded classification.
// --patterns (two_tag, ssl, team_only or a pattern file) warns of the colours that pattern
// puts on robots which the table has no cell for.
// Exit status: 0 on success, 2 for bad arguments, unreadable/invalid inputs or an output that
// cannot be written (with a message naming the problem).
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;

namespace {

struct Options {
  std::vector<std::string> images;
  std::vector<std::string> samples;
  std::string out;
  std::string preview;
  sv::ColorTableParams params;
  sv::CalibrationLight light = sv::CalibrationLight::Normalized;
  std::vector<double> spread;  // --spread L,AB
  std::string patterns;        // --patterns: warn of its colours the table has no cell for
};

void addOptions(CLI::App& app, Options& o, std::vector<int>& bins, std::string& light) {
  app.add_option("--image", o.images, "calibration image (PNG, BGR); repeat for more")
      ->required()
      ->take_all();
  app.add_option("--samples", o.samples, "sample polygons (YAML) per image, or one for all; repeat for more")
      ->required()
      ->take_all();
  app.add_option("--out", o.out, "the colour table to write (.svct)")->required();
  app.add_option("--preview", o.preview, "write the first image beside its classification (PNG)");
  app.add_option("--threshold-lab", o.params.threshold_lab, "CIE76 distance to a class's mean Lab")
      ->capture_default_str();
  app.add_option("--threshold-h", o.params.threshold_h, "[deg] hue distance to a class's mean hue")
      ->capture_default_str();
  app.add_option("--bins", bins, "H,S,V bins of the table (default 90,16,16)")
      ->delimiter(',')
      ->check(CLI::Range(1, 720));
  app.add_option("--v-margin", o.params.v_margin, "V bins added below and above a class's samples")
      ->check(CLI::Range(0, 255))
      ->capture_default_str();
  app.add_option(
         "--generalize", o.params.generalize_sigmas,
         "[sigmas] claim every cell within this Mahalanobis distance of a class's L*a*b* Gaussian; 0: off")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  app.add_option("--spread", o.spread, "[ΔE] L*,ab spread added to each class's Gaussian (default 6,5)")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::Range(0.01, 100.0));
  app.add_option("--brightness-spread", o.params.brightness_spread,
                 "share of brightness a robot marker's samples also stand for, darker and brighter; 0: off")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  app.add_option("--print-spread", o.params.print_spread,
                 "share by which one channel of a robot marker's samples may differ in another print; 0: off")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  app.add_option("--ball-carpet-mix", o.params.ball_carpet_mix,
                 "share of the carpet's colour the ball's samples are also mixed with; 0: off")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  app.add_option("--ball-carpet-unmix", o.params.ball_carpet_unmix,
                 "share of the carpet's colour also taken out of the ball's samples (a blurred ball); 0: off")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  app.add_option(
         "--fallback", o.params.fallback_sigmas,
         "[sigmas] a cell no class claimed goes to the nearest robot marker class within this; 0: off")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  app.add_option("--fallback-guard", o.params.fallback_guard_sigmas,
                 "[sigmas] ... only if every other class (carpet, lines, robot tops, ball) is beyond this")
      ->check(CLI::Range(0.0, 20.0))
      ->capture_default_str();
  app.add_option("--clipped-variants", o.params.clipped_variants,
                 "robot markers also as clipped under the images' brightest light (true/false)")
      ->capture_default_str();
  app.add_option("--clipped-twice-path", o.params.clipped_twice_path,
                 "robot markers also where two channels clip, up to the images' brightest light (true/false)")
      ->capture_default_str();
  app.add_option("--clipped-cells-own", o.params.clipped_cells_own,
                 "a colour a robot marker sample shows clipped twice stays that class's (true/false)")
      ->capture_default_str();
  app.add_option("--other-prints", o.params.other_prints,
                 "a robot marker sampled mostly outside its class's valid colours is another print of it "
                 "(true/false)")
      ->capture_default_str();
  app.add_option("--lines-yield-to-markers", o.params.lines_yield_to_markers,
                 "a colour both the lines and a robot marker claim is the marker's (true/false)")
      ->capture_default_str();
  app.add_option("--light", light, "normalized (by the illumination reference) or as-captured")
      ->check(CLI::IsMember(std::vector<std::string>{"normalized", "as-captured"}))
      ->capture_default_str();
  app.add_option(
      "--patterns", o.patterns,
      "marker patterns (two_tag, ssl, team_only or a file): warn of their colours the table lacks");
}

// Options that do not go together, bins and thresholds out of range: a message, or "".
std::string optionProblem(Options& o, const std::vector<int>& bins, const std::string& light) {
  if (!bins.empty()) {
    if (bins.size() != 3) return "--bins takes H,S,V";
    o.params.h_bins = bins[0];
    o.params.s_bins = bins[1];
    o.params.v_bins = bins[2];
  }
  if (!o.spread.empty()) {
    o.params.spread_l = o.spread[0];
    o.params.spread_ab = o.spread[1];
  }
  o.light = light == "as-captured" ? sv::CalibrationLight::AsCaptured : sv::CalibrationLight::Normalized;
  if (o.samples.size() != 1 && o.samples.size() != o.images.size())
    return std::to_string(o.images.size()) + " images but " + std::to_string(o.samples.size()) +
           " samples files: give one per image or one for all";
  try {
    o.params.validate();  // bins and thresholds in range
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

std::vector<sv::CalibrationImage> loadInputs(const Options& o) {
  std::vector<sv::CalibrationImage> inputs;
  std::vector<sv::ColorSamples> samples;
  for (const std::string& path : o.samples) samples.push_back(sv::loadColorSamples(path));
  for (std::size_t i = 0; i < o.images.size(); ++i) {
    sv::CalibrationImage in;
    in.bgr = cv::imread(o.images[i], cv::IMREAD_COLOR);
    if (in.bgr.empty())
      throw std::runtime_error("cannot read image '" + o.images[i] + "' (missing or not an image)");
    if (!inputs.empty() && in.bgr.size() != inputs.front().bgr.size())
      throw std::runtime_error("image '" + o.images[i] + "' is " + std::to_string(in.bgr.cols) + "x" +
                               std::to_string(in.bgr.rows) + ", '" + o.images.front() + "' is " +
                               std::to_string(inputs.front().bgr.cols) + "x" +
                               std::to_string(inputs.front().bgr.rows) +
                               ": calibration images must have one size");
    in.samples = samples[samples.size() == 1 ? 0 : i];
    if (in.samples.empty())
      throw std::runtime_error("samples file '" + o.samples[samples.size() == 1 ? 0 : i] +
                               "' has no polygons");
    inputs.push_back(std::move(in));
  }
  return inputs;
}

// Every class given polygons must select pixels in at least one image (polygons outside the
// images or too thin to contain a pixel centre are a mistake, not an empty class).
void checkSamplesSelectPixels(const Options& o, const std::vector<sv::CalibrationImage>& inputs) {
  std::map<sv::ColorClass, std::size_t> selected;
  for (const sv::CalibrationImage& in : inputs) {
    for (const auto& [cls, polygons] : in.samples) selected[cls] += 0;
    for (const auto& [cls, px] : sv::collectSamplePixels(in.bgr, in.samples)) selected[cls] += px.size();
  }
  for (const auto& [cls, n] : selected) {
    if (n == 0)
      throw std::runtime_error(
          "the polygons of class '" + std::string(sv::colorClassName(cls)) + "' in " +
          (o.samples.size() == 1 ? "'" + o.samples.front() + "'" : std::string("the samples files")) +
          " select no pixel of the image(s): outside the image or too "
          "thin to contain a pixel centre");
  }
}

void printStatistics(const sv::ColorTable& table) {
  const sv::ColorTableStatistics& st = table.statistics();
  const sv::ColorTableParams& p = table.params();
  std::printf("colour table: %d x %d x %d cells (H x S x V)\n", p.h_bins, p.s_bins, p.v_bins);
  std::printf("%-10s %8s %8s %22s %7s %9s %7s %8s %8s\n", "class", "samples", "valid", "mean Lab", "mean H",
              "thr Lab", "thr H", "claimed", "held");
  for (int c = 1; c < sv::kNumColorClasses; ++c) {
    const sv::ClassStatistics& s = st.classes[c];
    if (s.samples == 0) continue;
    char lab[64];
    std::snprintf(lab, sizeof(lab), "(%.1f, %.1f, %.1f)", s.mean_lab.l, s.mean_lab.a, s.mean_lab.b);
    char thr_h[16];
    if (s.thresholds.h > 180)
      std::snprintf(thr_h, sizeof(thr_h), "off");
    else
      std::snprintf(thr_h, sizeof(thr_h), "%.1f", s.thresholds.h);
    std::printf("%-10s %8u %8u %22s %7.1f %9.1f %7s %8u %8u\n",
                std::string(sv::colorClassName(static_cast<sv::ColorClass>(c))).c_str(), s.samples, s.valid,
                lab, s.mean_h, s.thresholds.lab, thr_h, s.cells_claimed, s.cells_assigned);
    if (s.valid == 0)
      std::printf(
          "  warning: no valid sample for %s: it claims no cell (check its polygons "
          "or raise the thresholds)\n",
          std::string(sv::colorClassName(static_cast<sv::ColorClass>(c))).c_str());
  }
  std::printf("cells claimed by more than one class, decided by Bayes: %u\n", st.overlap_cells);
}

void writePreview(const std::string& path, const sv::ColorTable& table, const cv::Mat& bgr) {
  const auto model = sv::SegmentationModel::fromTable(std::make_shared<const sv::ColorTable>(table));
  const cv::Mat labels = sv::classifyAll(*model, bgr, sv::PixelLayout::Bgr);
  cv::Mat side_by_side;
  cv::hconcat(bgr, sv::colorizeLabels(labels), side_by_side);
  bool ok = false;
  try {
    ok = cv::imwrite(path, side_by_side);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot write preview '" + path + "': " + e.what());
  }
  if (!ok) throw std::runtime_error("cannot write preview '" + path + "'");
  std::printf("preview (image | classification): %s\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::vector<int> bins;
  std::string light = "normalized";
  CLI::App app{
      "calibrate_colors: a colour table (.svct) from images and sample polygons (docs/calibration.md)",
      "calibrate_colors"};
  addOptions(app, o, bins, light);
  if (const auto status = sv::parseCommandLine(app, argc, argv)) return *status;
  if (const std::string problem = optionProblem(o, bins, light); !problem.empty())
    return sv::usageError(app, problem);
  try {
    const std::vector<sv::CalibrationImage> inputs = loadInputs(o);
    checkSamplesSelectPixels(o, inputs);
    const std::optional<sv::PatternSet> patterns =
        o.patterns.empty() ? std::nullopt : std::optional(sv::patternSetByName(o.patterns));
    const sv::ColorTable table = sv::calibrateColorTable(inputs, o.params, o.light);
    table.save(o.out);
    std::printf("calibrated from %zu image(s) of %dx%d\n", inputs.size(), inputs.front().bgr.cols,
                inputs.front().bgr.rows);
    printStatistics(table);
    for (const std::string& w : sv::calibrationWarnings(inputs, table, patterns ? &*patterns : nullptr))
      std::printf("warning: %s\n", w.c_str());
    std::printf("written: %s\n", o.out.c_str());
    if (!o.preview.empty()) writePreview(o.preview, table, inputs.front().bgr);
  } catch (const std::exception& e) {
    std::cerr << "calibrate_colors: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
