#include "soccer_vision/illumination_adaptation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace soccer_vision {

cv::Mat blockMeanV(const cv::Mat& image, PixelLayout layout, int sample_step) {
  checkImageFitsLayout(image, layout);
  if (sample_step < 1) throw std::invalid_argument("blockMeanV: sample_step must be >= 1");
  const int block = BlockOffsets::kBlockSize / (isBayer(layout) ? 2 : 1);  // in label pixels
  const cv::Size labels = labelSize(image.size(), layout);
  const int block_rows = (image.rows + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize;
  const int block_cols = (image.cols + BlockOffsets::kBlockSize - 1) / BlockOffsets::kBlockSize;
  cv::Mat means(block_rows, block_cols, CV_32FC1);
  std::vector<std::uint32_t> sums(static_cast<std::size_t>(block_cols));
  for (int by = 0; by < block_rows; ++by) {
    std::fill(sums.begin(), sums.end(), 0u);
    const int y0 = by * block, y1 = std::min(y0 + block, labels.height);
    for (int y = y0; y < y1; y += sample_step) {
      const LabelRow row = labelRow(image, layout, y);
      for (int bx = 0; bx < block_cols; ++bx) {
        const int x1 = std::min((bx + 1) * block, labels.width);
        std::uint32_t sum = 0;
        for (int i = bx * block * row.step; i < x1 * row.step; i += sample_step * row.step) {
          sum += static_cast<std::uint32_t>(std::max({int(row.b[i]), (row.g1[i] + row.g2[i] + 1) >> 1, int(row.r[i])}));
        }
        sums[static_cast<std::size_t>(bx)] += sum;
      }
    }
    const int rows_read = (y1 - y0 + sample_step - 1) / sample_step;
    float* out = means.ptr<float>(by);
    for (int bx = 0; bx < block_cols; ++bx) {
      const int width = std::min((bx + 1) * block, labels.width) - bx * block;
      const int read = rows_read * ((width + sample_step - 1) / sample_step);
      out[bx] = static_cast<float>(static_cast<double>(sums[static_cast<std::size_t>(bx)]) / read);
    }
  }
  return means;
}

IlluminationAdaptation IlluminationAdaptation::fromImages(const std::vector<cv::Mat>& images, PixelLayout layout) {
  if (images.empty()) throw std::invalid_argument("illumination reference: no images");
  cv::Mat sum;
  for (const cv::Mat& image : images) {
    if (image.size() != images.front().size()) {
      throw std::invalid_argument("illumination reference: images of different sizes");
    }
    const cv::Mat means = blockMeanV(image, layout);
    if (sum.empty()) {
      means.convertTo(sum, CV_64FC1);
    } else {
      cv::Mat m;
      means.convertTo(m, CV_64FC1);
      sum += m;
    }
  }
  cv::Mat reference;
  sum.convertTo(reference, CV_32FC1, 1.0 / static_cast<double>(images.size()));
  return IlluminationAdaptation(reference);
}

BlockOffsets IlluminationAdaptation::offsets(const cv::Mat& image, PixelLayout layout, double k, int sample_step,
                                             int max_offset, bool* size_mismatch) const {
  if (max_offset < 0 || max_offset > 255) {
    throw std::invalid_argument("illumination offsets: max_offset must be in 0..255 (beyond, V saturates)");
  }
  if (size_mismatch) *size_mismatch = false;
  if (k == 0.0 || reference_.empty()) return {};
  if (reference_.type() != CV_32FC1) throw std::invalid_argument("illumination reference must be CV_32FC1");
  const cv::Mat now = blockMeanV(image, layout, sample_step);
  if (now.size() != reference_.size()) {
    if (size_mismatch) *size_mismatch = true;
    return {};
  }
  BlockOffsets out;
  out.offsets.create(now.size(), CV_16SC1);
  for (int y = 0; y < now.rows; ++y) {
    const float* ref = reference_.ptr<float>(y);
    const float* cur = now.ptr<float>(y);
    std::int16_t* o = out.offsets.ptr<std::int16_t>(y);
    for (int x = 0; x < now.cols; ++x) {
      const double delta = std::clamp(k * (static_cast<double>(ref[x]) - cur[x]), -1e4, 1e4);
      o[x] = static_cast<std::int16_t>(std::clamp<long>(std::lround(delta), -max_offset, max_offset));
    }
  }
  return out;
}

}  // namespace soccer_vision
