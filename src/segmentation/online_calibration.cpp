#include "soccer_vision/segmentation/online_calibration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "soccer_vision/common/color_space.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/segmentation/illumination_adaptation.h"

namespace soccer_vision {

namespace {

// The envelope is never narrower than this per axis (1σ): one frame's few pixels per colour
// understate how a colour spreads over prints, places and light.
constexpr double kMinSigmaH = 5.0;   // degrees
constexpr double kMinSigmaS = 0.05;  // of [0, 1]
constexpr double kMinSigmaV = 16.0;  // 8-bit levels

// Background pixels are not read within this many radii of a region's centre: a robot's
// top, rim and the markers segmentation missed lie within it.
constexpr double kExclusionRadii = 4.0;

// Learned band centres stay within this factor of the calibrated levels.
constexpr float kMaxLevelFactor = 8.0f;

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("online calibration: " + what);
}

// A region as a disc in label pixels (a Bayer quad (x, y) has its centre at image pixel
// 2x + 0.5): its centre and the radius of a disc of its second moments (mu20 = mu02 = r² / 4).
struct LabelDisc {
  double cx, cy, r;
  bool finite() const { return std::isfinite(cx) && std::isfinite(cy) && std::isfinite(r); }
};
LabelDisc labelDisc(const Region& region, PixelLayout layout) {
  const bool quads = isBayer(layout);
  const double scale = quads ? 0.5 : 1.0;
  return {(quads ? region.cx - 0.5 : region.cx) * scale, (quads ? region.cy - 0.5 : region.cy) * scale,
          std::sqrt(2.0 * std::max(0.0, region.mu20 + region.mu02)) * scale};
}

double circularDifference(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return d;
}

}  // namespace

void OnlineCalibrationParams::validate() const {
  require(std::isfinite(interior) && interior > 0 && interior <= 1, "interior must be in (0, 1]");
  require(std::isfinite(update_period) && update_period > 0 && update_period <= 3600,
          "update_period must be in (0, 3600] s");
  require(min_votes >= 1 && min_votes <= 1000000, "min_votes must be in 1..1000000");
  require(std::isfinite(purity) && purity >= 0.5 && purity <= 1, "purity must be in [0.5, 1]");
  require(std::isfinite(learn_sigmas) && learn_sigmas >= 0 && learn_sigmas <= 20,
          "learn_sigmas must be in [0, 20]");
  require(max_cells_per_update >= 0 && max_cells_per_update <= 1000000,
          "max_cells_per_update must be in 0..1000000");
  require(max_learned_cells >= 0 && max_learned_cells <= 1000000, "max_learned_cells must be in 0..1000000");
  require(background_stride >= 1 && background_stride <= 1024, "background_stride must be in 1..1024");
  require(std::isfinite(level_rate) && level_rate >= 0 && level_rate <= 1, "level_rate must be in [0, 1]");
}

std::uint32_t OnlineCalibrationStatus::learnedTotal() const {
  std::uint32_t n = 0;
  for (const std::uint32_t c : learned_cells) n += c;
  return n;
}

OnlineCalibration::OnlineCalibration(std::shared_ptr<const SegmentationModel> base,
                                     const OnlineCalibrationParams& params)
    : params_(params), base_(std::move(base)), model_(base_) {
  require(base_ && base_->classifier, "no base model");
  params_.validate();
  reset();
}

void OnlineCalibration::setParams(const OnlineCalibrationParams& params) {
  params.validate();
  params_ = params;
}

void OnlineCalibration::reset() {
  const std::size_t cells = base_->classifier->table().cells().size();
  votes_.assign(cells, Votes{});
  learned_.assign(cells, ColorClass::None);
  expected_.release();
  light_shape_.release();
  have_stamp_ = false;
  status_ = OnlineCalibrationStatus{};
  model_ = base_;
}

std::size_t OnlineCalibration::cellOf(const cv::Vec3b& bgr, int adapted_v) const {
  const ColorTable& table = base_->classifier->table();
  const Hsv hsv = bgrToHsv(bgr[0], bgr[1], bgr[2]);
  return table.cellIndex(table.hBin(hsv.h), table.sBin(hsv.s), table.vBin(adapted_v));
}

void OnlineCalibration::voteMarker(const FrameClassifier& frame, const Region& region, PixelLayout layout) {
  if (!isMarkerColor(region.color)) return;
  const LabelDisc disc = labelDisc(region, layout);
  if (!disc.finite()) return;
  const double cx = disc.cx, cy = disc.cy, r = params_.interior * disc.r;
  const cv::Size size = frame.labelSize();
  const int x0 = std::max(0, static_cast<int>(std::floor(cx - r)));
  const int x1 = std::min(size.width - 1, static_cast<int>(std::ceil(cx + r)));
  const int y0 = std::max(0, static_cast<int>(std::floor(cy - r)));
  const int y1 = std::min(size.height - 1, static_cast<int>(std::ceil(cy + r)));
  const int c = static_cast<int>(region.color);
  std::uint64_t voted = 0;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > r * r) continue;
      votes_[cellOf(frame.colorAt(x, y), frame.adaptedV(x, y))].marker[c] += 1.0f;
      ++voted;
    }
  }
  // A marker smaller than one pixel's distance: its nearest pixel.
  const int nx = static_cast<int>(std::lround(cx)), ny = static_cast<int>(std::lround(cy));
  if (voted == 0 && nx >= 0 && ny >= 0 && nx < size.width && ny < size.height) {
    votes_[cellOf(frame.colorAt(nx, ny), frame.adaptedV(nx, ny))].marker[c] += 1.0f;
    voted = 1;
  }
  ++status_.markers;
  status_.marker_votes += voted;
}

void OnlineCalibration::voteBackground(const FrameClassifier& frame, const std::vector<Region>& regions,
                                       PixelLayout layout) {
  const int stride = params_.background_stride;
  const cv::Size size = frame.labelSize();
  const int cols = (size.width + stride - 1) / stride, rows = (size.height + stride - 1) / stride;
  cv::Mat1b excluded(rows, cols, std::uint8_t(0));
  for (const Region& region : regions) {
    const LabelDisc disc = labelDisc(region, layout);
    if (!disc.finite()) continue;
    const double cx = disc.cx, cy = disc.cy, r = kExclusionRadii * disc.r + 1.0;
    const int gx0 = std::max(0, static_cast<int>(std::floor((cx - r) / stride)));
    const int gx1 = std::min(cols - 1, static_cast<int>(std::ceil((cx + r) / stride)));
    const int gy0 = std::max(0, static_cast<int>(std::floor((cy - r) / stride)));
    const int gy1 = std::min(rows - 1, static_cast<int>(std::ceil((cy + r) / stride)));
    for (int gy = gy0; gy <= gy1; ++gy) {
      for (int gx = gx0; gx <= gx1; ++gx) {
        const double dx = gx * stride - cx, dy = gy * stride - cy;
        if (dx * dx + dy * dy <= r * r) excluded(gy, gx) = 1;
      }
    }
  }
  for (int gy = 0; gy < rows; ++gy) {
    for (int gx = 0; gx < cols; ++gx) {
      if (excluded(gy, gx)) continue;
      const int x = gx * stride, y = gy * stride;
      votes_[cellOf(frame.colorAt(x, y), frame.adaptedV(x, y))].background += 1.0f;
      ++status_.background_votes;
    }
  }
}

void OnlineCalibration::observe(const cv::Mat& image, PixelLayout layout, const BlockOffsets& offsets,
                                double sharpen, const std::vector<Region>& regions,
                                const std::vector<int>& confirmed, double stamp) {
  if (!params_.enabled) return;
  const FrameClassifier frame(*model_->classifier, image, layout, offsets, sharpen);
  for (const int i : confirmed) {
    if (i >= 0 && static_cast<std::size_t>(i) < regions.size()) voteMarker(frame, regions[i], layout);
  }
  voteBackground(frame, regions, layout);
  ++status_.frames;
  // The light's shape is read (a full pass over the frame) only when an update is due.
  const bool due = have_stamp_ && stamp >= status_.last_update_stamp &&
                   stamp - status_.last_update_stamp >= params_.update_period;
  if (due && params_.level_rate > 0 && base_->illumination.normalizes() &&
      base_->illumination.referenceLevels().size() ==
          cv::Size((image.cols + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize,
                   (image.rows + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize)) {
    light_shape_ = expectedLightLevels(image, layout);
  }
}

bool OnlineCalibration::insideEnvelope(std::size_t cell, ColorClass c) const {
  const ColorTable& table = base_->classifier->table();
  const ClassStatistics& s = table.statistics().classes[static_cast<int>(c)];
  if (s.valid == 0) return false;  // a class never calibrated is never learned
  const ColorTableParams& q = table.params();
  const int v_bin = static_cast<int>(cell % q.v_bins);
  const int s_bin = static_cast<int>((cell / q.v_bins) % q.s_bins);
  const int h_bin = static_cast<int>(cell / (static_cast<std::size_t>(q.v_bins) * q.s_bins));
  const double h = (h_bin + 0.5) * 360.0 / q.h_bins, sat = (s_bin + 0.5) / q.s_bins,
               v = (v_bin + 0.5) * 256.0 / q.v_bins;
  const double dh = circularDifference(h, s.mean_h_valid) / std::max(std::sqrt(s.var_h), kMinSigmaH);
  const double ds = (sat - s.mean_s) / std::max(std::sqrt(s.var_s), kMinSigmaS);
  const double dv = (v - s.mean_v) / std::max(std::sqrt(s.var_v), kMinSigmaV);
  return dh * dh + ds * ds + dv * dv <= params_.learn_sigmas * params_.learn_sigmas;
}

bool OnlineCalibration::updateCells() {
  const std::vector<ColorClass>& base = base_->classifier->table().cells();
  bool changed = false;
  std::uint32_t learned = status_.learnedTotal();
  std::vector<std::pair<float, std::size_t>> candidates;
  std::vector<ColorClass> candidate_class(base.size(), ColorClass::None);
  status_.vetoed_cells = status_.outside_envelope = 0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    Votes& v = votes_[i];
    if (learned_[i] != ColorClass::None) {
      // Background seen in a learned cell: give it back.
      if (v.background > 0) {
        --status_.learned_cells[static_cast<int>(learned_[i])];
        --learned;
        learned_[i] = ColorClass::None;
        ++status_.cells_removed;
        changed = true;
      }
    } else if (base[i] == ColorClass::None) {
      int best = 0;
      float total = 0;
      for (int c = 1; c < kNumColorClasses; ++c) {
        total += v.marker[c];
        if (v.marker[c] > v.marker[best]) best = c;
      }
      if (best != 0 && v.marker[best] >= params_.min_votes && v.marker[best] >= params_.purity * total) {
        if (v.background > 0) {
          ++status_.vetoed_cells;
        } else if (!insideEnvelope(i, static_cast<ColorClass>(best))) {
          ++status_.outside_envelope;
        } else {
          candidates.emplace_back(v.marker[best], i);
          candidate_class[i] = static_cast<ColorClass>(best);
        }
      }
    }
    for (float& m : v.marker) m *= 0.5f;  // old light is forgotten
  }
  // The best supported first, within the rate and the total bound.
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  int added = 0;
  for (const auto& [votes, i] : candidates) {
    if (added >= params_.max_cells_per_update ||
        learned >= static_cast<std::uint32_t>(params_.max_learned_cells))
      break;
    learned_[i] = candidate_class[i];
    ++status_.learned_cells[static_cast<int>(learned_[i])];
    ++learned;
    ++added;
    ++status_.cells_added;
    changed = true;
  }
  return changed;
}

bool OnlineCalibration::updateLight() {
  if (light_shape_.empty()) return false;
  const cv::Mat1f levels = base_->illumination.referenceLevels();
  const cv::Mat1f now = light_shape_;
  light_shape_.release();
  if (levels.empty() || now.size() != levels.size()) return false;
  const cv::Mat1f old = expected_.empty() ? levels.clone() : cv::Mat1f(expected_);
  std::vector<double> ratios;
  ratios.reserve(now.total());
  for (int y = 0; y < now.rows; ++y) {
    for (int x = 0; x < now.cols; ++x) ratios.push_back(now(y, x) / old(y, x));
  }
  const double global = percentile(ratios, 50);
  if (!std::isfinite(global) || global <= 0) return false;
  // Towards the frame's shape (its global change divided out), geometrically by level_rate,
  // then scaled back to the calibrated levels' median: the band follows the shape, the
  // global change is measured every frame.
  cv::Mat1f next(now.size());
  std::vector<double> scale;
  scale.reserve(now.total());
  for (int y = 0; y < now.rows; ++y) {
    for (int x = 0; x < now.cols; ++x) {
      const double r = std::max(1e-3, now(y, x) / old(y, x) / global);
      next(y, x) = static_cast<float>(old(y, x) * std::pow(r, params_.level_rate));
      scale.push_back(next(y, x) / levels(y, x));
    }
  }
  const double median_scale = percentile(scale, 50);
  double change = 0, deviation = 0;
  for (int y = 0; y < now.rows; ++y) {
    for (int x = 0; x < now.cols; ++x) {
      const float bounded = std::clamp(static_cast<float>(next(y, x) / median_scale),
                                       levels(y, x) / kMaxLevelFactor, levels(y, x) * kMaxLevelFactor);
      next(y, x) = bounded;
      change = std::max(change, std::abs(bounded / old(y, x) - 1.0));
      deviation = std::max(deviation, std::abs(bounded / levels(y, x) - 1.0));
    }
  }
  // Below 1 % the band does not move enough to matter: no new model.
  if (change < 0.01) return false;
  expected_ = next;
  status_.level_deviation = deviation;
  return true;
}

std::shared_ptr<const SegmentationModel> OnlineCalibration::update(double stamp) {
  if (!params_.enabled || !std::isfinite(stamp)) return nullptr;
  if (!have_stamp_ || stamp < status_.last_update_stamp) {
    have_stamp_ = true;
    status_.last_update_stamp = stamp;
    return nullptr;
  }
  if (stamp - status_.last_update_stamp < params_.update_period) return nullptr;
  status_.last_update_stamp = stamp;
  ++status_.updates;
  const bool cells = updateCells();
  const bool light = updateLight();
  if (!cells && !light) return nullptr;
  ++status_.models;
  auto m = std::make_shared<SegmentationModel>();
  if (cells) {
    std::vector<std::pair<std::size_t, ColorClass>> list;
    for (std::size_t i = 0; i < learned_.size(); ++i) {
      if (learned_[i] != ColorClass::None) list.emplace_back(i, learned_[i]);
    }
    m->classifier = std::make_shared<PixelClassifier>(
        std::make_shared<const ColorTable>(base_->classifier->table().withCells(list)));
  } else {
    m->classifier = model_->classifier;
  }
  // The ball's streak table stays the calibrated table's: what is learned here is the
  // robots' markers and the carpet, never the ball.
  m->streak_classifier = base_->streak_classifier;
  m->illumination = base_->illumination.withExpectedLevels(expected_);
  model_ = std::move(m);
  return model_;
}

}  // namespace soccer_vision
