#include "soccer_vision/segmentation/illumination_adaptation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace soccer_vision {
namespace {

float median(std::vector<float>& values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// std::lround for 0 <= v < 2^52, inline: v - trunc(v) is exact there, so halves round
// away from zero as lround does.
long roundPositive(double v) {
  const auto whole = static_cast<long>(v);
  return whole + (v - static_cast<double>(whole) >= 0.5 ? 1 : 0);
}

// The block grid of an image: block side in label pixels, label size, rows and columns.
struct BlockGrid {
  BlockGrid(const cv::Mat& image, PixelLayout layout)
      : block(BlockOffsets::kBlockSize / (isBayer(layout) ? 2 : 1)),
        labels(labelSize(image.size(), layout)),
        rows((image.rows + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize),
        cols((image.cols + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize) {}
  int block;
  cv::Size labels;
  int rows, cols;
};

int labelV(const LabelRow& row, int i) {
  return std::max({int(row.b[i]), (row.g1[i] + row.g2[i] + 1) >> 1, int(row.r[i])});
}

// Sum and count of the V values in [lo, lo + width] of label pixels x0, x0 + step, ... < x1
// of a row. Unsigned range test: one compare per pixel for lo <= v <= lo + width.
template <int Step>
void sumInBand(const LabelRow& row, int x0, int x1, int step, unsigned lo, unsigned width, std::uint32_t& sum,
               std::uint32_t& count) {
  std::uint32_t s = 0, n = 0;
  for (int i = x0 * Step; i < x1 * Step; i += step * Step) {
    const int g = Step == 3 ? row.g1[i] : (row.g1[i] + row.g2[i] + 1) >> 1;  // bgr8/rgb8: one green
    const unsigned v = static_cast<unsigned>(std::max({int(row.b[i]), g, int(row.r[i])}));
    const bool in_band = v - lo <= width;
    s += in_band ? v : 0u;
    n += in_band;
  }
  sum += s;
  count += n;
}

void checkBlockMap(const cv::Mat& map, const BlockGrid& grid, const char* what) {
  if (map.type() != CV_32FC1 || map.size() != cv::Size(grid.cols, grid.rows)) {
    throw std::invalid_argument(std::string(what) + " must be a CV_32FC1 of the image's block grid");
  }
}

void checkSelection(const cv::Mat1b& selected, const BlockGrid& grid, const char* what) {
  if (!selected.empty() && selected.size() != cv::Size(grid.cols, grid.rows)) {
    throw std::invalid_argument(std::string(what) +
                                ": the block selection must be of the image's block grid");
  }
}

}  // namespace

cv::Mat1b blocksMeeting(const cv::Mat& image, PixelLayout layout, const std::vector<cv::Rect>& rects) {
  const BlockGrid grid(image, layout);
  cv::Mat1b selected(grid.rows, grid.cols, std::uint8_t(0));
  const cv::Rect all(0, 0, grid.cols, grid.rows);
  constexpr int b = BlockOffsets::kBlockSize;
  for (const cv::Rect& r : rects) {
    if (r.empty()) continue;
    const int x0 = r.x >= 0 ? r.x / b : -1, y0 = r.y >= 0 ? r.y / b : -1;
    const int x1 = (r.x + r.width - 1) / b + 1, y1 = (r.y + r.height - 1) / b + 1;
    const cv::Rect blocks = cv::Rect(x0, y0, x1 - x0, y1 - y0) & all;
    if (!blocks.empty()) selected(blocks).setTo(1);
  }
  return selected;
}

cv::Mat blockMeanV(const cv::Mat& image, PixelLayout layout, int sample_step, const cv::Mat1b& selected) {
  checkImageFitsLayout(image, layout);
  if (sample_step < 1) throw std::invalid_argument("blockMeanV: sample_step must be >= 1");
  checkSelection(selected, BlockGrid(image, layout), "blockMeanV");
  const int block = BlockOffsets::kBlockSize / (isBayer(layout) ? 2 : 1);  // in label pixels
  const cv::Size labels = labelSize(image.size(), layout);
  const int block_rows = (image.rows + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize;
  const int block_cols = (image.cols + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize;
  cv::Mat means(block_rows, block_cols, CV_32FC1);
  std::vector<LabelRow> rows;
  for (int by = 0; by < block_rows; ++by) {
    const std::uint8_t* wanted = selected.empty() ? nullptr : selected.ptr<std::uint8_t>(by);
    float* out = means.ptr<float>(by);
    const int y0 = by * block, y1 = std::min(y0 + block, labels.height);
    rows.clear();  // the rows read, located once per block row
    if (!wanted || std::any_of(wanted, wanted + block_cols, [](std::uint8_t w) { return w != 0; })) {
      for (int y = y0; y < y1; y += sample_step) rows.push_back(labelRow(image, layout, y));
    }
    for (int bx = 0; bx < block_cols; ++bx) {
      if (wanted && !wanted[bx]) {
        out[bx] = 0.0f;
        continue;
      }
      const int x1 = std::min((bx + 1) * block, labels.width);
      std::uint32_t sum = 0;
      for (const LabelRow& row : rows) {
        for (int i = bx * block * row.step; i < x1 * row.step; i += sample_step * row.step) {
          sum += static_cast<std::uint32_t>(
              std::max({int(row.b[i]), (row.g1[i] + row.g2[i] + 1) >> 1, int(row.r[i])}));
        }
      }
      const int width = x1 - bx * block;
      const int read = static_cast<int>(rows.size()) * ((width + sample_step - 1) / sample_step);
      out[bx] = static_cast<float>(static_cast<double>(sum) / read);
    }
  }
  return means;
}

cv::Mat blockLightLevels(const cv::Mat& image, PixelLayout layout, const cv::Mat& expected, int sample_step,
                         const cv::Mat1b& selected) {
  checkImageFitsLayout(image, layout);
  if (sample_step < 1) throw std::invalid_argument("blockLightLevels: sample_step must be >= 1");
  const BlockGrid grid(image, layout);
  checkBlockMap(expected, grid, "blockLightLevels: the expected levels");
  checkSelection(selected, grid, "blockLightLevels");
  cv::Mat levels(grid.rows, grid.cols, CV_32FC1);
  // 0: no reading (covered), 1: a reading, 2: a clean one (mostly carpet).
  cv::Mat1b measured(grid.rows, grid.cols, std::uint8_t(0));
  std::vector<float> ratios;
  std::vector<LabelRow> rows;
  for (int by = 0; by < grid.rows; ++by) {
    const float* e = expected.ptr<float>(by);
    const std::uint8_t* wanted = selected.empty() ? nullptr : selected.ptr<std::uint8_t>(by);
    if (wanted && std::none_of(wanted, wanted + grid.cols, [](std::uint8_t w) { return w != 0; })) continue;
    const int y0 = by * grid.block, y1 = std::min(y0 + grid.block, grid.labels.height);
    rows.clear();  // the rows read, located once per block row
    for (int y = y0; y < y1; y += sample_step) rows.push_back(labelRow(image, layout, y));
    float* out = levels.ptr<float>(by);
    for (int bx = 0; bx < grid.cols; ++bx) {
      if (wanted && !wanted[bx]) continue;
      const int low = static_cast<int>(std::ceil(kLevelBandLow * e[bx]));
      const int high = std::max(low, static_cast<int>(std::floor(kLevelBandHigh * e[bx])));
      const auto lo = static_cast<unsigned>(low), width = static_cast<unsigned>(high - low);
      const int x0 = bx * grid.block, x1 = std::min(x0 + grid.block, grid.labels.width);
      std::uint32_t sum = 0, count = 0;
      for (const LabelRow& row : rows) {
        if (row.step == 3) {
          sumInBand<3>(row, x0, x1, sample_step, lo, width, sum, count);
        } else {
          sumInBand<2>(row, x0, x1, sample_step, lo, width, sum, count);
        }
      }
      const auto read = static_cast<std::uint32_t>(rows.size() * ((x1 - x0 + sample_step - 1) / sample_step));
      if (count > 0 && count >= kMinLevelFraction * read) {
        measured(by, bx) = count >= kCleanLevelFraction * read ? 2 : 1;
        out[bx] = static_cast<float>(static_cast<double>(sum) / count);
        ratios.push_back(out[bx] / e[bx]);
      }
    }
  }
  // Where a robot takes much of a block, the edges of its top and markers are a good part of
  // the pixels left in the band, and bias the block's reading; the light is smooth over a
  // few blocks. A block without a clean reading of its own takes the median ratio to
  // `expected` of the clean readings around it, else of all readings around it, else of
  // all blocks.
  const float fill = ratios.empty() ? 1.0f : median(ratios);
  cv::Mat1f ratio(grid.rows, grid.cols, 0.0f);
  for (int by = 0; by < grid.rows; ++by) {
    const std::uint8_t* m = measured.ptr<std::uint8_t>(by);
    const float* e = expected.ptr<float>(by);
    const float* level = levels.ptr<float>(by);
    float* r = ratio.ptr<float>(by);
    for (int bx = 0; bx < grid.cols; ++bx) {
      if (m[bx]) r[bx] = level[bx] / e[bx];
    }
  }
  std::vector<float> clean, any;
  for (int by = 0; by < grid.rows; ++by) {
    const std::uint8_t* wanted = selected.empty() ? nullptr : selected.ptr<std::uint8_t>(by);
    const std::uint8_t* m = measured.ptr<std::uint8_t>(by);
    const float* e = expected.ptr<float>(by);
    float* out = levels.ptr<float>(by);
    for (int bx = 0; bx < grid.cols; ++bx) {
      if (m[bx] == 2) continue;
      clean.clear();
      any.clear();
      if (!wanted || wanted[bx]) {
        for (int j = std::max(0, by - kLevelNeighbourhood);
             j <= std::min(grid.rows - 1, by + kLevelNeighbourhood); ++j) {
          const std::uint8_t* mj = measured.ptr<std::uint8_t>(j);
          const float* rj = ratio.ptr<float>(j);
          for (int i = std::max(0, bx - kLevelNeighbourhood);
               i <= std::min(grid.cols - 1, bx + kLevelNeighbourhood); ++i) {
            if (mj[i] == 2) clean.push_back(rj[i]);
            if (mj[i]) any.push_back(rj[i]);
          }
        }
      }
      out[bx] = (!clean.empty() ? median(clean) : !any.empty() ? median(any) : fill) * e[bx];
    }
  }
  return levels;
}

cv::Mat expectedLightLevels(const cv::Mat& image, PixelLayout layout) {
  checkImageFitsLayout(image, layout);
  const BlockGrid grid(image, layout);
  cv::Mat1f medians(grid.rows, grid.cols);
  std::vector<float> values;
  for (int by = 0; by < grid.rows; ++by) {
    for (int bx = 0; bx < grid.cols; ++bx) {
      values.clear();
      for (int y = by * grid.block; y < std::min((by + 1) * grid.block, grid.labels.height); ++y) {
        const LabelRow row = labelRow(image, layout, y);
        for (int x = bx * grid.block; x < std::min((bx + 1) * grid.block, grid.labels.width); ++x) {
          values.push_back(static_cast<float>(labelV(row, x * row.step)));
        }
      }
      medians(by, bx) = median(values);
    }
  }
  constexpr int radius = 2;
  cv::Mat1f expected(medians.size());
  for (int by = 0; by < grid.rows; ++by) {
    for (int bx = 0; bx < grid.cols; ++bx) {
      values.clear();
      for (int j = std::max(0, by - radius); j <= std::min(grid.rows - 1, by + radius); ++j) {
        for (int i = std::max(0, bx - radius); i <= std::min(grid.cols - 1, bx + radius); ++i)
          values.push_back(medians(j, i));
      }
      expected(by, bx) = std::max(median(values), 1.0f);  // a black image still has a positive level
    }
  }
  return std::move(expected);
}

IlluminationAdaptation IlluminationAdaptation::fromImages(const std::vector<cv::Mat>& images,
                                                          PixelLayout layout) {
  if (images.empty()) throw std::invalid_argument("illumination reference: no images");
  cv::Mat sum, level_sum;
  for (const cv::Mat& image : images) {
    if (image.size() != images.front().size()) {
      throw std::invalid_argument("illumination reference: images of different sizes");
    }
    cv::Mat means, levels;
    blockMeanV(image, layout).convertTo(means, CV_64FC1);
    blockLightLevels(image, layout, expectedLightLevels(image, layout)).convertTo(levels, CV_64FC1);
    sum = sum.empty() ? means : sum + means;
    level_sum = level_sum.empty() ? levels : level_sum + levels;
  }
  cv::Mat reference, levels;
  sum.convertTo(reference, CV_32FC1, 1.0 / static_cast<double>(images.size()));
  level_sum.convertTo(levels, CV_32FC1, 1.0 / static_cast<double>(images.size()));
  return IlluminationAdaptation(reference, levels);
}

BlockOffsets IlluminationAdaptation::gainsFor(const cv::Mat& levels) const {
  if (levels_.empty()) return {};
  if (levels.type() != CV_32FC1 || levels.size() != levels_.size()) {
    throw std::invalid_argument(
        "illumination gains: levels must be a CV_32FC1 of the reference's block grid");
  }
  const double mean_level = mean_level_;
  BlockOffsets out;
  out.gains.create(levels.size(), CV_16UC1);
  for (int y = 0; y < levels.rows; ++y) {
    const float* level = levels.ptr<float>(y);
    std::uint16_t* gain = out.gains.ptr<std::uint16_t>(y);
    for (int x = 0; x < levels.cols; ++x) {
      const double g = ColorTable::kUnitGain * mean_level / std::max(level[x], 1e-3f);
      gain[x] = static_cast<std::uint16_t>(std::clamp<long>(
          roundPositive(std::min(g, 1e6)), ColorTable::kUnitGain / 8, 8 * ColorTable::kUnitGain));
    }
  }
  return out;
}

cv::Mat IlluminationAdaptation::currentLevels(const cv::Mat& image, PixelLayout layout, int sample_step,
                                              const cv::Mat1b& selected) const {
  // The band follows a global change first, so that it still holds the carpet when the
  // whole field got much brighter or darker than at calibration.
  double global = 1.0;
  if (!reference_.empty() && reference_.size() == levels_.size()) {
    const cv::Mat now = blockMeanV(image, layout, 2 * sample_step, selected);
    std::vector<float> ratios;
    ratios.reserve(now.total());
    for (int y = 0; y < now.rows; ++y) {
      const float* ref = reference_.ptr<float>(y);
      const float* mean = now.ptr<float>(y);
      const std::uint8_t* wanted = selected.empty() ? nullptr : selected.ptr<std::uint8_t>(y);
      for (int x = 0; x < now.cols; ++x) {
        if (ref[x] > 0 && (!wanted || wanted[x])) ratios.push_back(mean[x] / ref[x]);
      }
    }
    if (!ratios.empty()) global = std::clamp<double>(median(ratios), 1.0 / 16, 16.0);
  }
  return blockLightLevels(image, layout, expectedLevels() * global, sample_step, selected);
}

IlluminationAdaptation IlluminationAdaptation::withExpectedLevels(const cv::Mat& expected) const {
  if (!expected.empty() && (expected.type() != CV_32FC1 || expected.size() != levels_.size() ||
                            !cv::checkRange(expected, true, nullptr, 1e-3, 1e6))) {
    throw std::invalid_argument(
        "illumination: expected levels must be a CV_32FC1 of finite positive levels of the reference "
        "levels' size");
  }
  IlluminationAdaptation out = *this;
  out.expected_ = expected.empty() ? cv::Mat() : expected.clone();
  return out;
}

BlockOffsets IlluminationAdaptation::offsets(const cv::Mat& image, PixelLayout layout, double k,
                                             int sample_step, int max_offset, bool* size_mismatch,
                                             const std::vector<cv::Rect>* windows) const {
  if (max_offset < 0 || max_offset > 255) {
    throw std::invalid_argument("illumination offsets: max_offset must be in 0..255 (beyond, V saturates)");
  }
  if (size_mismatch) *size_mismatch = false;
  const cv::Mat& reference = normalizes() ? levels_ : reference_;
  if (reference.empty()) return {};
  if (reference.type() != CV_32FC1) throw std::invalid_argument("illumination reference must be CV_32FC1");
  const BlockGrid grid(image, layout);
  if (reference.size() != cv::Size(grid.cols, grid.rows)) {
    checkImageFitsLayout(image, layout);
    if (size_mismatch) *size_mismatch = true;
    return {};
  }
  const cv::Mat1b selected = windows ? blocksMeeting(image, layout, *windows) : cv::Mat1b();
  if (!normalizes()) return paperOffsets(image, layout, k, sample_step, max_offset, selected);
  return gainsFor(k == 0.0 ? levels_ : currentLevels(image, layout, sample_step, selected));
}

BlockOffsets IlluminationAdaptation::paperOffsets(const cv::Mat& image, PixelLayout layout, double k,
                                                  int sample_step, int max_offset,
                                                  const cv::Mat1b& selected) const {
  if (k == 0.0) return {};
  const cv::Mat now = blockMeanV(image, layout, sample_step, selected);
  BlockOffsets out;
  out.offsets.create(now.size(), CV_16SC1);
  for (int y = 0; y < now.rows; ++y) {
    const float* ref = reference_.ptr<float>(y);
    const float* cur = now.ptr<float>(y);
    std::int16_t* o = out.offsets.ptr<std::int16_t>(y);
    for (int x = 0; x < now.cols; ++x) {
      // Blocks left out of the selection get no offset (nothing there is classified).
      const bool skipped = !selected.empty() && !selected(y, x);
      const double delta = skipped ? 0.0 : std::clamp(k * (static_cast<double>(ref[x]) - cur[x]), -1e4, 1e4);
      o[x] = static_cast<std::int16_t>(std::clamp<long>(std::lround(delta), -max_offset, max_offset));
    }
  }
  return out;
}

}  // namespace soccer_vision
