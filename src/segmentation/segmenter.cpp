#include "soccer_vision/segmentation/segmenter.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "soccer_vision/common/class_colors.h"
#include "soccer_vision/segmentation/floor_surround.h"

namespace soccer_vision {
namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Image pixels -> label pixels: Bayer labels are 2x2 quads, so a window covers every quad
// it touches.
cv::Rect toLabelRect(const cv::Rect& r, PixelLayout layout) {
  if (!isBayer(layout)) return r;
  const int x0 = r.x >> 1, y0 = r.y >> 1;
  const int x1 = (r.x + r.width + 1) >> 1, y1 = (r.y + r.height + 1) >> 1;
  return {x0, y0, x1 - x0, y1 - y0};
}

// Bayer label rectangle -> the image pixels its quads cover.
cv::Rect quadsToImage(const cv::Rect& r) { return {r.x * 2, r.y * 2, r.width * 2, r.height * 2}; }

// Label coordinates -> image pixels: quad (x, y) covers pixels 2x..2x+1, centre 2x + 0.5.
void toImageCoordinates(Region& r) {
  r.cx = 2 * r.cx + 0.5;
  r.cy = 2 * r.cy + 0.5;
  r.mu20 *= 4;
  r.mu11 *= 4;
  r.mu02 *= 4;
  r.area *= 4;
  r.bbox = quadsToImage(r.bbox);
}

// `windows` clipped to the image, those left empty dropped, into `rects` (image pixels) and
// `label_rects` (label coordinates).
void clipWindows(const std::vector<cv::Rect>& windows, cv::Size image, PixelLayout layout,
                 std::vector<cv::Rect>& rects, std::vector<cv::Rect>& label_rects) {
  const cv::Rect image_rect(0, 0, image.width, image.height);
  rects.clear();
  label_rects.clear();
  for (const cv::Rect& w : windows) {
    const cv::Rect clipped = w & image_rect;
    if (clipped.empty()) continue;
    rects.push_back(clipped);
    label_rects.push_back(toLabelRect(clipped, layout));
  }
}

}  // namespace

std::shared_ptr<const SegmentationModel> SegmentationModel::fromTable(std::shared_ptr<const ColorTable> table,
                                                                      const BallStreakParams& streak) {
  auto model = std::make_shared<SegmentationModel>();
  model->illumination = IlluminationAdaptation(table->illuminationReference(), table->illuminationLevels());
  if (auto streaks = ballStreakTable(*table, streak)) {
    model->streak_classifier =
        std::make_shared<PixelClassifier>(std::make_shared<const ColorTable>(std::move(*streaks)));
  }
  model->classifier = std::make_shared<PixelClassifier>(std::move(table));
  return model;
}

RegionParams labelParams(const RegionParams& p, int label_width) {
  const double r = std::min(1.0, label_width / static_cast<double>(kRegionParamsWidth));
  if (r >= 1.0) return p;
  RegionParams q = p;
  // The k x k opening must not erase the smallest markers. Measured on uneven_drift (a
  // camera over half the field): the 3x3 opening keeps every robot down to 960 px wide
  // (0.8 mm), at 780 px (a 30 mm tag ~4.5 px) it finds 71 % and at 640 px none; off (or
  // k / 2) they are 100 %. Bayer quads at 1280 px are the 640 px case: 2 is 2.4x faster (a
  // stride-2 grid) but opens away the partly covered edge quads of the small tags: 96.4 %
  // of robots and 6 mm RMSE instead of 99.7 % and 3 mm. (The default is 2 since: a
  // wide-angle lens' corners at 1280 px, RegionParams::morph_kernel.)
  if (r < kKeepKernelRatio)
    q.morph_kernel = p.morph_kernel > 1 ? std::max(1, p.morph_kernel / 2) : p.morph_kernel;
  // Without the opening, regions must still hold two adjacent pixels of their class
  // (require_pair): every marker does, single noise pixels (the most common false
  // regions of Bayer quads) do not, and the scan reads a checkerboard, half the pixels.
  if (p.morph_kernel > 1 && q.morph_kernel <= 1) q.require_pair = true;
  q.min_area = std::max(1, static_cast<int>(std::lround(p.min_area * r * r)));
  q.max_area = std::max(q.min_area, static_cast<int>(std::lround(p.max_area * r * r)));
  q.tile_size = std::max(8, static_cast<int>(std::lround(p.tile_size * r)));
  return q;
}

RegionParams quadLabelParams(const RegionParams& p) { return labelParams(p, kRegionParamsWidth / 2); }

Segmenter::Segmenter(const SegmentationParams& params) : params_(params) {}

void Segmenter::setParams(const SegmentationParams& params) {
  params_ = params;
  extractor_.width = streak_extractor_.width = -1;  // remade with these parameters at first use
}

RegionExtractor& Segmenter::extractorFor(SizedExtractor& e, int label_width, ClassMask classes) {
  if (label_width != e.width) {
    RegionParams p = labelParams(params_.regions, label_width);
    p.classes = classes;
    e.extractor = RegionExtractor(p);
    e.width = label_width;
  }
  return e.extractor;
}

void Segmenter::findBallStreaks(const SegmentationModel& model, const FrameClassifier& colors,
                                const cv::Mat& image, PixelLayout layout,
                                const std::vector<cv::Rect>& streak_windows, SegmentationResult& out) {
  std::vector<cv::Rect> rects, label_rects;
  clipWindows(streak_windows, image.size(), layout, rects, label_rects);
  if (rects.empty()) return;
  const FrameClassifier frame(*model.streak_classifier, image, layout, out.offsets, params_.sharpen);
  std::vector<Region> streaks;
  RegionStatistics stats;
  extractorFor(streak_extractor_, labelSize(image.size(), layout).width, classBit(ColorClass::Orange))
      .extract(frame, label_rects, streaks, stats);
  // A ball lies on the floor: a cluster the colour table does not read as floor around (a
  // yellow tag on a robot's dark top that the streak table takes for a blurred ball; held-out
  // seed 9090's rand_fast) is refused, and the colour table's orange stays there.
  std::vector<cv::Rect> refused;
  if (params_.ball_streak_floor_share > 0) {
    streaks.erase(std::remove_if(streaks.begin(), streaks.end(),
                                 [&](const Region& r) {
                                   const auto share = floorShareAround(colors, r);
                                   if (!share || *share >= params_.ball_streak_floor_share) return false;
                                   refused.push_back(r.bbox);
                                   return true;
                                 }),
                  streaks.end());
  }
  if (isBayer(layout)) {
    for (auto& r : streaks) toImageCoordinates(r);
    for (auto& b : refused) b = quadsToImage(b);
  }
  // The colour table's orange regions in those windows are parts of what the streak table
  // finds there (it holds every orange cell): replaced, not counted twice.
  auto inside = [](const Region& r, const cv::Rect& w) {
    return r.cx >= w.x && r.cy >= w.y && r.cx < w.x + w.width && r.cy < w.y + w.height;
  };
  auto inAny = [&](const Region& r, const std::vector<cv::Rect>& boxes) {
    return std::any_of(boxes.begin(), boxes.end(), [&](const cv::Rect& w) { return inside(r, w); });
  };
  out.regions.erase(std::remove_if(out.regions.begin(), out.regions.end(),
                                   [&](const Region& r) {
                                     return r.color == ColorClass::Orange && inAny(r, rects) &&
                                            !inAny(r, refused);
                                   }),
                    out.regions.end());
  for (Region& r : streaks) {
    if (!inAny(r, rects)) continue;
    out.regions.push_back(std::move(r));
    ++out.streak_regions;
  }
  out.streak_refused = static_cast<std::uint32_t>(refused.size());
  out.streak_windows = static_cast<std::uint32_t>(rects.size());
  for (std::size_t c = 0; c < out.fringes.size(); ++c) out.fringes[c] += stats.fringes[c];
  out.timings.classification_ms += stats.classify_ms;
  out.timings.morphology_ms += stats.morphology_ms;
  out.timings.regions_ms += stats.regions_ms;
}

void Segmenter::process(const SegmentationModel& model, const cv::Mat& image, PixelLayout layout,
                        const std::vector<cv::Rect>& windows, SegmentationResult& out,
                        const std::vector<cv::Rect>& streak_windows) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<cv::Rect> label_windows;
  clipWindows(windows, image.size(), layout, out.windows, label_windows);
  // Windows that all fall outside the image leave nothing to search; a global search is
  // only what the caller asked for with no windows at all.
  out.global_search = windows.empty();

  out.offsets =
      model.illumination.offsets(image, layout, params_.illumination_k, params_.illumination_sample_step,
                                 params_.max_illumination_offset, &out.illumination_size_mismatch,
                                 out.global_search ? nullptr : &out.windows);
  out.timings.illumination_ms = msSince(start);

  const FrameClassifier frame(*model.classifier, image, layout, out.offsets, params_.sharpen);
  RegionStatistics stats;
  out.regions.clear();
  if (out.global_search || !label_windows.empty()) {
    extractorFor(extractor_, labelSize(image.size(), layout).width, params_.regions.classes)
        .extract(frame, label_windows, out.regions, stats);
  }
  if (isBayer(layout)) {
    for (auto& r : out.regions) toImageCoordinates(r);
  }
  out.cap_hits = stats.cap_hits;
  out.fringes = stats.fringes;
  out.grid_points = stats.grid_points;
  out.classified_pixels = stats.classified_pixels;
  out.timings.classification_ms = stats.classify_ms;
  out.timings.morphology_ms = stats.morphology_ms;
  out.timings.regions_ms = stats.regions_ms;
  out.streak_windows = out.streak_regions = out.streak_refused = 0;
  if (params_.ball_streaks && model.streak_classifier)
    findBallStreaks(model, frame, image, layout, streak_windows, out);
  out.timings.total_ms = msSince(start);
}

bool searchesLostBallStreaks(PixelLayout layout) { return !isBayer(layout); }

std::vector<cv::Rect> streakWindows(PixelLayout layout, const std::vector<cv::Rect>& ball_streak,
                                    const std::vector<cv::Rect>& lost_ball_streak) {
  std::vector<cv::Rect> out = ball_streak;
  if (searchesLostBallStreaks(layout))
    out.insert(out.end(), lost_ball_streak.begin(), lost_ball_streak.end());
  return out;
}

cv::Mat classifyAll(const SegmentationModel& model, const cv::Mat& image, PixelLayout layout,
                    const SegmentationParams& params) {
  const BlockOffsets offsets = model.illumination.offsets(
      image, layout, params.illumination_k, params.illumination_sample_step, params.max_illumination_offset);
  const FrameClassifier frame(*model.classifier, image, layout, offsets, params.sharpen);
  const cv::Size size = frame.labelSize();
  cv::Mat labels(size, CV_8UC1);
  frame.classify(cv::Rect(0, 0, size.width, size.height), labels);
  return labels;
}

cv::Mat colorizeLabels(const cv::Mat& labels) {
  CV_Assert(labels.type() == CV_8UC1);
  cv::Vec3b palette[256] = {};
  for (int c = 1; c < kNumColorClasses; ++c) {
    const cv::Vec3f a = classAlbedo(static_cast<ColorClass>(c));
    palette[c] = cv::Vec3b(cv::saturate_cast<uchar>(a[0]), cv::saturate_cast<uchar>(a[1]),
                           cv::saturate_cast<uchar>(a[2]));
  }
  cv::Mat out(labels.size(), CV_8UC3);
  for (int y = 0; y < labels.rows; ++y) {
    const uchar* in = labels.ptr<uchar>(y);
    cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < labels.cols; ++x) o[x] = palette[in[x]];
  }
  return out;
}

}  // namespace soccer_vision
