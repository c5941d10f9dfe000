#include "soccer_vision/segmentation/run_length_components.h"

#include <algorithm>

namespace soccer_vision {
namespace {

// First x in [from, limit) whose bit equals `set`, or limit. Bits beyond the width are 0.
int nextBit(const std::uint64_t* row, int from, int limit, bool set) {
  if (from >= limit) return limit;
  int w = from >> 6;
  std::uint64_t bits = (set ? row[w] : ~row[w]) & (~std::uint64_t(0) << (from & 63));
  const int last_word = (limit - 1) >> 6;
  while (bits == 0) {
    if (++w > last_word) return limit;
    bits = set ? row[w] : ~row[w];
  }
  return std::min(limit, 64 * w + __builtin_ctzll(bits));
}

// Sum of x² for x in [0, n).
std::int64_t sumOfSquaresBelow(std::int64_t n) { return (n - 1) * n * (2 * n - 1) / 6; }

}  // namespace

int RunLengthComponents::findRoot(int run) {
  while (parent_[run] != run) {
    parent_[run] = parent_[parent_[run]];  // path halving
    run = parent_[run];
  }
  return run;
}

void RunLengthComponents::compute(const BitMask& mask, const cv::Rect& rect) {
  runs_.clear();
  row_begin_.assign(1, 0);
  parent_.clear();
  for (int y = 0; y < rect.height; ++y) {
    const std::uint64_t* row = mask.row(rect.y + y);
    const int limit = rect.br().x;
    for (int x = nextBit(row, rect.x, limit, true); x < limit;) {
      const int end = nextBit(row, x, limit, false);
      runs_.push_back({y, x - rect.x, end - rect.x, -1});
      x = nextBit(row, end, limit, true);
    }
    row_begin_.push_back(static_cast<int>(runs_.size()));
  }

  // Join runs of consecutive rows that share a column or touch at a corner; the root is
  // always the run that comes first in raster order.
  parent_.resize(runs_.size());
  for (std::size_t i = 0; i < runs_.size(); ++i) parent_[i] = static_cast<int>(i);
  for (int y = 1; y < rect.height; ++y) {
    int above = row_begin_[static_cast<std::size_t>(y) - 1];
    const int above_end = row_begin_[static_cast<std::size_t>(y)];
    for (int r = row_begin_[static_cast<std::size_t>(y)]; r < row_begin_[static_cast<std::size_t>(y) + 1];
         ++r) {
      const PixelRun& run = runs_[static_cast<std::size_t>(r)];
      while (above < above_end && runs_[static_cast<std::size_t>(above)].x_end < run.x_begin) ++above;
      for (int a = above; a < above_end && runs_[static_cast<std::size_t>(a)].x_begin <= run.x_end; ++a) {
        const int ra = findRoot(a), rr = findRoot(r);
        if (ra < rr) parent_[static_cast<std::size_t>(rr)] = ra;
        if (rr < ra) parent_[static_cast<std::size_t>(ra)] = rr;
      }
    }
  }

  // Number the roots in raster order; accumulate the statistics run by run.
  components_.clear();
  std::vector<int> counts;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    PixelRun& run = runs_[i];
    const int root = findRoot(static_cast<int>(i));
    if (root == static_cast<int>(i)) {
      run.component = static_cast<int>(components_.size());
      components_.push_back({});
      components_.back().bbox = cv::Rect(run.x_begin, run.y, run.x_end - run.x_begin, 1);
      counts.push_back(0);
    } else {
      run.component = runs_[static_cast<std::size_t>(root)].component;
    }
    ComponentStats& c = components_[static_cast<std::size_t>(run.component)];
    ++counts[static_cast<std::size_t>(run.component)];
    const std::int64_t n = run.x_end - run.x_begin, y = run.y;
    const std::int64_t sum_x = n * (run.x_begin + run.x_end - 1) / 2;
    c.area += static_cast<std::uint32_t>(n);
    c.bbox |= cv::Rect(run.x_begin, run.y, run.x_end - run.x_begin, 1);
    c.sum_x += sum_x;
    c.sum_y += n * y;
    c.sum_xx += sumOfSquaresBelow(run.x_end) - sumOfSquaresBelow(run.x_begin);
    c.sum_xy += sum_x * y;
    c.sum_yy += n * y * y;
  }

  // Runs grouped by component (a counting sort keeps the raster order within each).
  component_begin_.assign(components_.size() + 1, 0);
  for (std::size_t c = 0; c < components_.size(); ++c)
    component_begin_[c + 1] = component_begin_[c] + counts[c];
  std::vector<int> next(component_begin_.begin(), component_begin_.end() - 1);
  runs_by_component_.resize(runs_.size());
  for (const PixelRun& run : runs_)
    runs_by_component_[static_cast<std::size_t>(next[static_cast<std::size_t>(run.component)]++)] = run;
}

int RunLengthComponents::componentAt(int x, int y) const {
  const auto begin = runs_.begin() + row_begin_[static_cast<std::size_t>(y)];
  const auto end = runs_.begin() + row_begin_[static_cast<std::size_t>(y) + 1];
  const auto after =
      std::upper_bound(begin, end, x, [](int px, const PixelRun& r) { return px < r.x_begin; });
  if (after == begin) return -1;
  const PixelRun& run = *(after - 1);
  return x < run.x_end ? run.component : -1;
}

const PixelRun* RunLengthComponents::runsBegin(int component) const {
  return runs_by_component_.data() + component_begin_[static_cast<std::size_t>(component)];
}

const PixelRun* RunLengthComponents::runsEnd(int component) const {
  return runs_by_component_.data() + component_begin_[static_cast<std::size_t>(component) + 1];
}

}  // namespace soccer_vision
