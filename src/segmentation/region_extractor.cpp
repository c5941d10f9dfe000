#include "soccer_vision/segmentation/region_extractor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "soccer_vision/segmentation/binary_morphology.h"
#include "soccer_vision/segmentation/mosaic_fringes.h"
#include "soccer_vision/segmentation/region_moments.h"
#include "soccer_vision/segmentation/run_length_components.h"

// How the exact result is found without classifying the frame (see the header for why the
// grid scan finds every region):
//  1. scan: grid points of the wanted classes; a hit is kept only when it lies in some
//     k x k square of its class (an erosion window), i.e. when it survives the opening
//     (a 5x5 look for k = 3), so colour noise costs a few pixels per hit, not a tile;
//  2. areas: tiles holding kept hits, grouped into rectangles (bounding boxes of
//     8-connected tile groups, merged while they overlap);
//  3. per area: label the rectangle plus a margin that absorbs the wrong border
//     assumptions of the four erode/dilate passes (classifying only the tiles within
//     reach of a kept hit, see classifiedLabels), open + close per class present (on
//     bit-packed masks), then 8-connected components inside the rectangle (from runs).
//     A region holding a hit that touches a side of the rectangle that is not the image
//     border may continue outside: the area grows by a tile on that side (merging with
//     areas it meets) and is redone;
//  4. regions holding a hit, within the area filter and (Bayer quads) not a colour fringe,
//     get their moments; then the cap.
// Both equal the centred opening + closing (cv::erode/cv::dilate with the anchors of
// binary_morphology.h; cv::morphologyEx for odd k) and cv::connectedComponentsWithStats
// (connectivity 8), which
// cost more in fixed overhead than in pixels on areas this small.

namespace soccer_vision {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point& since) {
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - since).count();
  since = now;
  return ms;
}

// Largest morphology kernel (binary_morphology.h takes up to 63).
constexpr int kMaxKernel = 31;

enum Side : unsigned { kLeft = 1, kTop = 2, kRight = 4, kBottom = 8 };

struct Area {
  cv::Rect core;  // label pixels whose result is exact; tile-aligned except at the image border
  bool done = false;
  std::vector<Region> regions;
};

}  // namespace

// Scratch buffers, reused from frame to frame (an extractor is used by one thread).
struct RegionScratch {
  std::vector<cv::Point> hits;
  std::vector<cv::Rect> scanned;           // the search windows in the image
  std::vector<std::pair<int, int>> spans;  // of the scan: the windows' union in a row or column
  std::vector<int> edges;                  // of the scan: the windows' top and bottom rows
  std::vector<std::pair<cv::Rect, std::uint8_t>> area_hits;  // seed box in the core, class
  cv::Mat patch;                                             // labels of the patch around a hit
  std::vector<std::uint8_t> pending;                         // per hit: its opening test is left to its area
  std::vector<std::uint8_t> tiles;     // per tile: 2 = within reach of a kept hit (after tileAreas)
  std::vector<std::uint8_t> labelled;  // per tile: TileLabels, how its labels are written in this frame
  std::vector<int> tile_stack;
  std::vector<Area> areas;
  cv::Mat labels;  // label image of the frame, valid inside the `labelled` tiles only
  BitMask mask;
  MorphologyScratch morphology;
  std::array<RunLengthComponents, kNumColorClasses> components;  // of the area being done, per class
  std::vector<std::pair<int, int>> found;  // (class, component) of its regions within the area filter
  std::vector<std::uint8_t> seeded;
  CoverageScratch coverage;
};

namespace {

using Scratch = RegionScratch;

// Number of multiples of `step` in [begin, end).
int multiplesIn(int begin, int end, int step) {
  if (end <= begin) return 0;
  const int first = (begin + step - 1) / step;
  const int last = (end - 1) / step;
  return std::max(0, last - first + 1);
}

// Sorted, overlapping or adjacent [begin, end) spans merged.
void mergeSpans(std::vector<std::pair<int, int>>& spans) {
  std::sort(spans.begin(), spans.end());
  std::size_t merged = 0;
  for (std::size_t i = 1; i < spans.size(); ++i) {
    if (spans[i].first <= spans[merged].second) {
      spans[merged].second = std::max(spans[merged].second, spans[i].second);
    } else {
      spans[++merged] = spans[i];
    }
  }
  if (!spans.empty()) spans.resize(merged + 1);
}

// The hits of the stride grid (or of the checkerboard x + y even) in the union of
// `rects` (inside the image), each point looked up once however the rects overlap (search
// windows around robots close to each other do), plus, for the stride grid, the last
// column and row of the image where rects reach them and the grid misses them. Returns
// the number of points looked up.
std::uint32_t scanUnion(const FrameClassifier& frame, const std::vector<cv::Rect>& rects, int stride,
                        bool checkerboard, const cv::Rect& image, ClassMask classes, Scratch& s) {
  if (rects.empty()) return 0;
  std::uint32_t looked_up = 0;
  auto& spans = s.spans;
  // Between consecutive window edges every row meets the same windows: their union's spans
  // are merged once per band of rows, and the stride grid of a span is scanned in one call.
  auto& edges = s.edges;
  edges.clear();
  for (const cv::Rect& r : rects) edges.insert(edges.end(), {r.y, r.br().y});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (std::size_t e = 0; e + 1 < edges.size(); ++e) {
    const int band_begin = edges[e], band_end = edges[e + 1];
    spans.clear();
    for (const cv::Rect& r : rects) {
      if (r.y <= band_begin && band_begin < r.br().y) spans.emplace_back(r.x, r.br().x);
    }
    mergeSpans(spans);
    for (const auto& [x0, x1] : spans) {
      if (checkerboard) {
        for (int y = band_begin; y < band_end; ++y) {
          const int first = x0 + ((x0 + y) & 1);
          frame.scanPoints(y, first, x1, 2, classes, s.hits);
          looked_up += static_cast<std::uint32_t>(first < x1 ? (x1 - first + 1) / 2 : 0);
        }
      } else {
        frame.scanGrid(cv::Rect(x0, band_begin, x1 - x0, band_end - band_begin), stride, classes, s.hits);
        looked_up += static_cast<std::uint32_t>(multiplesIn(x0, x1, stride) *
                                                multiplesIn(band_begin, band_end, stride));
      }
    }
  }
  if (checkerboard) return looked_up;  // every domino in the image holds a checkerboard point
  bool corner_scanned = false;         // the last column's scan holds (width - 1, height - 1)
  if ((image.width - 1) % stride != 0) {
    spans.clear();
    for (const cv::Rect& r : rects) {
      if (r.br().x == image.width) spans.emplace_back(r.y, r.br().y);
    }
    mergeSpans(spans);
    for (const auto& [y0, y1] : spans) {
      frame.scanGrid(cv::Rect(image.width - 1, y0, 1, y1 - y0), 1, classes, s.hits);
      looked_up += static_cast<std::uint32_t>(y1 - y0);
      corner_scanned = corner_scanned || y1 == image.height;
    }
  }
  if ((image.height - 1) % stride != 0) {
    spans.clear();
    for (const cv::Rect& r : rects) {
      if (r.br().y == image.height)
        spans.emplace_back(r.x, r.br().x - (corner_scanned && r.br().x == image.width ? 1 : 0));
    }
    mergeSpans(spans);
    for (const auto& [x0, x1] : spans) {
      if (x1 <= x0) continue;
      frame.scanGrid(cv::Rect(x0, image.height - 1, x1 - x0, 1), 1, classes, s.hits);
      looked_up += static_cast<std::uint32_t>(x1 - x0);
    }
  }
  return looked_up;
}

// True when grid point `g` lies in some erosion window of the k x k opening that is
// entirely of its class: exactly the points that survive the opening. As in
// cv::morphologyEx, the outside of the image counts as the class for erosion, and only
// windows of in-image anchor pixels (anchor k/2) exist. `label(x, y)`: the label of an
// image pixel in g ± (k - 1). The window centred on g (it always exists) first: inside a
// marker that one passes.
template <typename LabelAt>
bool inOpenedWindow(const LabelAt& label, const cv::Rect& image, cv::Point g, int k) {
  const std::uint8_t color = label(g.x, g.y);
  const int anchor = k / 2;
  auto window_of_class = [&](int x0, int y0) {  // the window with top-left pixel (x0, y0)
    const int anchor_x = x0 + anchor, anchor_y = y0 + anchor;
    if (anchor_x < 0 || anchor_x >= image.width || anchor_y < 0 || anchor_y >= image.height) return false;
    for (int y = std::max(y0, 0); y < std::min(y0 + k, image.height); ++y) {
      for (int x = std::max(x0, 0); x < std::min(x0 + k, image.width); ++x) {
        if (label(x, y) != color) return false;
      }
    }
    return true;
  };
  const cv::Point centred(g.x - anchor, g.y - anchor);
  if (window_of_class(centred.x, centred.y)) return true;
  for (int y0 = g.y - (k - 1); y0 <= g.y; ++y0) {
    for (int x0 = g.x - (k - 1); x0 <= g.x; ++x0) {
      if (cv::Point(x0, y0) != centred && window_of_class(x0, y0)) return true;
    }
  }
  return false;
}

// True when point `g` has a 4-neighbour (in the image) of its class: it is part of a
// domino. `label(x, y)`: the label of an image pixel within g ± 1.
template <typename LabelAt>
bool inPair(const LabelAt& label, const cv::Rect& image, cv::Point g) {
  const std::uint8_t color = label(g.x, g.y);
  return (g.x > 0 && label(g.x - 1, g.y) == color) ||
         (g.x + 1 < image.width && label(g.x + 1, g.y) == color) ||
         (g.y > 0 && label(g.x, g.y - 1) == color) ||
         (g.y + 1 < image.height && label(g.x, g.y + 1) == color);
}

// What a grid hit must show to be kept: a k x k window of its class (the opening, or k = 1:
// nothing) or a domino (require_pair). reach(): how far from the hit the test looks.
struct HitRule {
  int k;
  bool pair;
  int reach() const { return pair ? 1 : k - 1; }
  bool filters() const { return pair || k > 1; }
  template <typename LabelAt>
  bool passes(const LabelAt& label, const cv::Rect& image, cv::Point g) const {
    return pair ? inPair(label, image, g) : inOpenedWindow(label, image, g, k);
  }
};

// The hit rule on the patch g ± reach, classified here (in one call). Adds the pixels it
// classified.
bool survivesRule(const FrameClassifier& frame, const cv::Rect& image, cv::Point g, const HitRule& rule,
                  ClassMask classes, cv::Mat& patch, std::uint32_t& classified) {
  const int reach = rule.reach();
  const cv::Rect inside = cv::Rect(g.x - reach, g.y - reach, 2 * reach + 1, 2 * reach + 1) & image;
  frame.classify(inside, patch, classes);
  classified += static_cast<std::uint32_t>(inside.area());
  return rule.passes([&](int x, int y) { return patch.at<std::uint8_t>(y - inside.y, x - inside.x); }, image,
                     g);
}

cv::Rect grownBy(const cv::Rect& r, int margin, const cv::Rect& image) {
  return cv::Rect(r.x - margin, r.y - margin, r.width + 2 * margin, r.height + 2 * margin) & image;
}

// Sides of `core` the box touches that are not the image border.
unsigned innerSidesTouched(const cv::Rect& box, const cv::Rect& core, const cv::Rect& image) {
  unsigned sides = 0;
  if (box.x == core.x && core.x > 0) sides |= kLeft;
  if (box.y == core.y && core.y > 0) sides |= kTop;
  if (box.br().x == core.br().x && core.br().x < image.width) sides |= kRight;
  if (box.br().y == core.br().y && core.br().y < image.height) sides |= kBottom;
  return sides;
}

cv::Rect grownOnSides(const cv::Rect& r, unsigned sides, int tile, const cv::Rect& image) {
  int x0 = r.x, y0 = r.y, x1 = r.br().x, y1 = r.br().y;
  if (sides & kLeft) x0 -= tile;
  if (sides & kTop) y0 -= tile;
  if (sides & kRight) x1 += tile;
  if (sides & kBottom) y1 += tile;
  return cv::Rect(x0, y0, x1 - x0, y1 - y0) & image;
}

// Rectangles merged while any two overlap.
void mergeOverlapping(std::vector<Area>& areas) {
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < areas.size() && !merged; ++i) {
      for (std::size_t j = i + 1; j < areas.size(); ++j) {
        if ((areas[i].core & areas[j].core).empty()) continue;
        areas[i].core |= areas[j].core;
        areas[i].done = false;
        areas.erase(areas.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
        break;
      }
    }
  }
}

// Where the region of a kept hit `g` lies for sure: at g itself — the centred opening
// keeps every pixel of a k x k square of the class and the closing only adds pixels
// (binary_morphology.h).
cv::Rect seedBox(cv::Point g, const cv::Rect& image) { return cv::Rect(g.x, g.y, 1, 1) & image; }

// Bounding rectangles (label pixels) of the 8-connected groups of tiles meeting a hit's
// box g ± reach. A region's opened pixels lie within k - 1 of its hits, so
// reach k - 1 gives areas that mostly hold their regions from the start: fewer of them
// grow and are redone (measured: 0.54 -> 0.51 ms for the windows of the benchmark).
void tileAreas(const std::vector<cv::Point>& hits, int tile, int reach, const cv::Rect& image, Scratch& s) {
  const int tiles_x = (image.width + tile - 1) / tile, tiles_y = (image.height + tile - 1) / tile;
  s.tiles.assign(static_cast<std::size_t>(tiles_x) * tiles_y, 0);
  for (const cv::Point& g : hits) {
    const cv::Rect box = grownBy(seedBox(g, image), reach, image);
    for (int ty = box.y / tile; ty <= (box.br().y - 1) / tile; ++ty) {
      for (int tx = box.x / tile; tx <= (box.br().x - 1) / tile; ++tx)
        s.tiles[static_cast<std::size_t>(ty) * tiles_x + tx] = 1;
    }
  }
  s.areas.clear();
  for (int start = 0; start < tiles_x * tiles_y; ++start) {
    if (s.tiles[start] != 1) continue;
    int x0 = tiles_x, y0 = tiles_y, x1 = -1, y1 = -1;
    s.tile_stack.assign(1, start);
    s.tiles[start] = 2;
    while (!s.tile_stack.empty()) {
      const int t = s.tile_stack.back();
      s.tile_stack.pop_back();
      const int tx = t % tiles_x, ty = t / tiles_x;
      x0 = std::min(x0, tx), y0 = std::min(y0, ty), x1 = std::max(x1, tx), y1 = std::max(y1, ty);
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = tx + dx, ny = ty + dy;
          if (nx < 0 || ny < 0 || nx >= tiles_x || ny >= tiles_y) continue;
          const int n = ny * tiles_x + nx;
          if (s.tiles[n] != 1) continue;
          s.tiles[n] = 2;
          s.tile_stack.push_back(n);
        }
      }
    }
    Area area;
    area.core = cv::Rect(x0 * tile, y0 * tile, (x1 - x0 + 1) * tile, (y1 - y0 + 1) * tile) & image;
    s.areas.push_back(std::move(area));
  }
  mergeOverlapping(s.areas);
}

// Per tile, how its labels are written in this frame (RegionScratch::labelled).
enum TileLabels : std::uint8_t { kUnwritten = 0, kClassified = 1, kWrittenNone = 2 };

// Whether label pixels of tile `t` within `reach` of its neighbour in direction (dx, dy)
// hold a class (the labels hold only the classes kept).
bool classNearSide(const cv::Mat& labels, const cv::Rect& t, int dx, int dy, int reach) {
  const int x0 = dx > 0 ? std::max(t.x, t.br().x - reach) : t.x;
  const int x1 = dx < 0 ? std::min(t.br().x, t.x + reach) : t.br().x;
  const int y0 = dy > 0 ? std::max(t.y, t.br().y - reach) : t.y;
  const int y1 = dy < 0 ? std::min(t.br().y, t.y + reach) : t.br().y;
  for (int y = y0; y < y1; ++y) {
    const std::uint8_t* row = labels.ptr<std::uint8_t>(y);
    for (int x = x0; x < x1; ++x) {
      if (row[x]) return true;
    }
  }
  return false;
}

// Labels of `rect`, a view into the frame's label image, written tile by tile, each tile
// classified at most once per frame however often its areas grow or merge. With morphology
// (`only_marked`) only the tiles within reach of a kept hit (tileAreas' 2s) or of unscanned
// pixels are classified; the others are written as None. With a grid of stride k that
// changes no region: the erosion finds the k x k squares of a class, each holds a kept hit
// within reach of all its pixels, so every such square lies in classified tiles, and a square
// that is all of a class here is classified, so one in truth too: the erosion is unchanged
// (inside the margin), and all that follows depends on it only. Packed robots' tile groups
// fill about half of their bounding boxes: in the crowd (32 robots) 61k instead of 112k
// pixels classified. A coarser grid (stride > k) may miss a region's squares, so `flood`
// > 0 classifies every tile of `rect` with a class pixel of a classified tile within
// `flood` px of it, until none is left: every class pixel within `flood` (>= k) of a
// classified one is then classified — the pixels a hit's region and what its closing joins
// to it are made of — and no tile left as None holds a class pixel within reach of them.
cv::Mat classifiedLabels(const FrameClassifier& frame, const cv::Rect& rect, int tile, int reach,
                         bool only_marked, int flood, ClassMask classes, Scratch& s,
                         std::uint32_t& classified) {
  const cv::Rect image(cv::Point(0, 0), s.labels.size());
  const int tiles_x = (image.width + tile - 1) / tile;
  const int tx_begin = rect.x / tile, tx_end = (rect.br().x - 1) / tile + 1;
  const int ty_begin = rect.y / tile, ty_end = (rect.br().y - 1) / tile + 1;
  auto tile_rect = [&](int tx, int ty) { return cv::Rect(tx * tile, ty * tile, tile, tile) & image; };
  auto classify_run = [&](const cv::Rect& run) {
    cv::Mat out = s.labels(run);
    frame.classify(run, out, classes);
    classified += static_cast<std::uint32_t>(run.area());
  };
  for (int ty = ty_begin; ty < ty_end; ++ty) {
    const std::size_t row = static_cast<std::size_t>(ty) * tiles_x;
    // A tile is left unclassified only where the grid was scanned within reach of it: a
    // region followed out of the search windows has no hits there.
    auto classify_tile = [&](int tx) {
      if (!only_marked || s.tiles[row + tx] == 2) return true;
      const cv::Rect near = grownBy(tile_rect(tx, ty), reach, image);
      for (const cv::Rect& scanned : s.scanned) {
        if ((near & scanned) == near) return false;
      }
      return true;
    };
    for (int tx = tx_begin; tx < tx_end;) {
      if (s.labelled[row + tx] != kUnwritten) {
        ++tx;
        continue;
      }
      // A run of unwritten tiles treated alike: one call, not one per tile.
      const bool classify = classify_tile(tx);
      int end = tx + 1;
      while (end < tx_end && s.labelled[row + end] == kUnwritten && classify_tile(end) == classify) ++end;
      std::fill(s.labelled.begin() + static_cast<std::ptrdiff_t>(row + tx),
                s.labelled.begin() + static_cast<std::ptrdiff_t>(row + end),
                classify ? kClassified : kWrittenNone);
      const cv::Rect run = cv::Rect(tx * tile, ty * tile, (end - tx) * tile, tile) & image;
      if (classify) {
        classify_run(run);
      } else {
        for (int y = run.y; y < run.br().y; ++y)
          std::fill_n(s.labels.ptr<std::uint8_t>(y) + run.x, run.width, 0);
      }
      tx = end;
    }
  }
  if (flood > 0) {
    auto& todo = s.tile_stack;
    todo.clear();
    for (int ty = ty_begin; ty < ty_end; ++ty) {
      for (int tx = tx_begin; tx < tx_end; ++tx) {
        if (s.labelled[static_cast<std::size_t>(ty) * tiles_x + tx] == kClassified)
          todo.push_back(ty * tiles_x + tx);
      }
    }
    while (!todo.empty()) {
      const int t = todo.back();
      todo.pop_back();
      const int tx = t % tiles_x, ty = t / tiles_x;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = tx + dx, ny = ty + dy;
          if ((dx == 0 && dy == 0) || nx < tx_begin || nx >= tx_end || ny < ty_begin || ny >= ty_end)
            continue;
          std::uint8_t& state = s.labelled[static_cast<std::size_t>(ny) * tiles_x + nx];
          if (state == kClassified || !classNearSide(s.labels, tile_rect(tx, ty), dx, dy, flood)) continue;
          state = kClassified;
          classify_run(tile_rect(nx, ny));
          todo.push_back(ny * tiles_x + nx);
        }
      }
    }
  }
  return s.labels(rect);
}

}  // namespace

int scanGridStride(const RegionParams& p) {
  return p.morph_kernel > 1 ? std::max(p.morph_kernel, p.scan_stride) : 1;
}

RegionExtractor::RegionExtractor(const RegionParams& params)
    : params_(params), scratch_(std::make_shared<RegionScratch>()) {
  const RegionParams& p = params_;
  if (p.morph_kernel < 0 || p.morph_kernel > kMaxKernel) {
    throw std::invalid_argument("RegionParams: morph_kernel must be in 0.." + std::to_string(kMaxKernel) +
                                ", got " + std::to_string(p.morph_kernel));
  }
  if (p.tile_size < 1) throw std::invalid_argument("RegionParams: tile_size must be >= 1");
  if (p.scan_stride < 0 || p.scan_stride > kMaxKernel) {
    throw std::invalid_argument("RegionParams: scan_stride must be in 0.." + std::to_string(kMaxKernel) +
                                ", got " + std::to_string(p.scan_stride));
  }
}

void RegionExtractor::extract(const FrameClassifier& frame, const std::vector<cv::Rect>& windows,
                              std::vector<Region>& regions, RegionStatistics& stats) {
  Scratch& s = *scratch_;
  regions.clear();
  stats = RegionStatistics{};
  const cv::Rect image(cv::Point(0, 0), frame.labelSize());
  const int k = params_.morph_kernel;
  const bool morphology = k > 1;
  const bool mosaic = isBayer(frame.layout()) && params_.min_agreeing_green_share > 0;
  // Every region kept holds a k x k square of its class (the opening) or, with
  // require_pair, a domino: the scan's grid and hit test follow from that.
  const HitRule rule{std::max(1, k), !morphology && params_.require_pair};
  const int stride = rule.pair ? 2 : scanGridStride(params_);
  // Tiles far from every kept hit are left unclassified; when a k x k square of a class may
  // hold no grid point (stride > k), the classification floods out from the classified tiles
  // along the classes' pixels (classifiedLabels).
  const bool only_marked = morphology;
  const int flood = only_marked && stride > k ? k : 0;
  const int tile = params_.tile_size;
  Clock::time_point since = Clock::now();

  // 1. Scan the union of the windows, each grid point once. Squares cut by the
  // right/bottom image border may miss the grid: their in-image part always holds the last
  // column/row, so those are scanned too (at stride 1).
  s.hits.clear();
  s.scanned.clear();
  if (s.labels.size() != image.size() || s.labels.type() != CV_8UC1) s.labels.create(image.size(), CV_8UC1);
  if (windows.empty()) s.scanned.push_back(image);
  for (const cv::Rect& w : windows) {
    if (!(w & image).empty()) s.scanned.push_back(w & image);
  }
  stats.grid_points += scanUnion(frame, s.scanned, stride, rule.pair, image, params_.classes, s);
  // In raster order (the scan goes band by band and span by span, and appends the last column
  // and row), so that each area finds its hits by rows instead of testing every hit.
  const auto raster = [](const cv::Point& a, const cv::Point& b) {
    return a.y != b.y ? a.y < b.y : a.x < b.x;
  };
  if (!std::is_sorted(s.hits.begin(), s.hits.end(), raster)) std::sort(s.hits.begin(), s.hits.end(), raster);
  // Hits that do not survive the opening are dropped (colour noise then costs a few
  // pixels per hit, not a tile). One surviving hit makes its tile part of an area, whose
  // classification will hold the patches of every other hit in it: those are tested
  // there, on the area's labels, instead of classifying their patches here.
  s.pending.clear();
  if (rule.filters()) {
    const int tiles_x = (image.width + tile - 1) / tile;
    s.tiles.assign(static_cast<std::size_t>(tiles_x) * ((image.height + tile - 1) / tile), 0);
    std::size_t kept = 0;
    for (const cv::Point& g : s.hits) {
      std::uint8_t& needed = s.tiles[static_cast<std::size_t>(g.y / tile) * tiles_x + g.x / tile];
      const bool pending = needed != 0;
      if (!pending && !survivesRule(frame, image, g, rule, params_.classes, s.patch, stats.classified_pixels))
        continue;
      needed = 1;
      s.hits[kept] = g;
      s.pending.push_back(pending);
      ++kept;
    }
    s.hits.resize(kept);
  } else {
    s.pending.assign(s.hits.size(), 0);
  }
  stats.classify_ms += msSince(since);

  // 2. Tile areas.
  tileAreas(s.hits, tile, rule.reach(), image, s);
  s.labelled.assign(s.tiles.size(), 0);
  // Four erode/dilate passes, each reaching k/2 px: beyond that the result is exact.
  const int margin = morphology ? 4 * (k / 2) : 0;

  // 3. Areas, grown until no region with a hit touches an inner side.
  for (;;) {
    auto pending = std::find_if(s.areas.begin(), s.areas.end(), [](const Area& a) { return !a.done; });
    if (pending == s.areas.end()) break;
    Area& area = *pending;
    area.regions.clear();
    const cv::Rect core = area.core;
    const cv::Rect outer = grownBy(core, margin, image);
    const cv::Mat labels = classifiedLabels(frame, outer, tile, rule.reach(), only_marked, flood,
                                            params_.classes, s, stats.classified_pixels);
    // Hits whose seed box reaches into the core, with their class.
    s.area_hits.clear();
    ClassMask present = 0;
    // Hits lie in the image, so a hit's seed box (its pixel) meets the core exactly when
    // the core contains it: the hits of the core's rows (they are in raster order), then a
    // test of x.
    const auto first_row = std::lower_bound(s.hits.begin(), s.hits.end(), core.y,
                                            [](const cv::Point& p, int y) { return p.y < y; });
    for (auto h = static_cast<std::size_t>(first_row - s.hits.begin());
         h < s.hits.size() && s.hits[h].y < core.br().y; ++h) {
      const cv::Point g = s.hits[h];
      if (g.x < core.x || g.x >= core.br().x) continue;
      const cv::Rect seeds = seedBox(g, image);
      // A pending hit's patch g ± reach lies in `outer` (tileAreas' reach, plus the margin).
      if (s.pending[h] &&
          !rule.passes([&](int x, int y) { return s.labels.at<std::uint8_t>(y, x); }, image, g)) {
        continue;
      }
      const std::uint8_t c = labels.at<std::uint8_t>(g - outer.tl());
      s.area_hits.push_back({seeds, c});
      present |= classBit(static_cast<ColorClass>(c));
    }
    stats.classify_ms += msSince(since);

    // Components of every class present first; moments only once the area is final
    // (no region touches an inner side), so that an area that grows wastes none.
    unsigned grow = 0;
    s.found.clear();
    const cv::Rect core_in_outer(core.tl() - outer.tl(), core.size());
    for (int c = 0; c < kNumColorClasses; ++c) {
      if (!(present & classBit(static_cast<ColorClass>(c)))) continue;
      s.mask.setFromLabels(labels, static_cast<std::uint8_t>(c));
      if (morphology) openThenClose(s.mask, k, s.morphology);
      stats.morphology_ms += msSince(since);

      RunLengthComponents& components = s.components[static_cast<std::size_t>(c)];
      components.compute(s.mask, core_in_outer);
      s.seeded.assign(components.components().size(), 0);
      for (const auto& [seeds, color] : s.area_hits) {
        if (color != c) continue;
        for (int y = seeds.y; y < seeds.br().y; ++y) {
          for (int x = seeds.x; x < seeds.br().x; ++x) {
            const int component = components.componentAt(x - core.x, y - core.y);
            if (component >= 0) s.seeded[static_cast<std::size_t>(component)] = 1;
          }
        }
      }
      for (std::size_t label = 0; label < s.seeded.size(); ++label) {
        if (!s.seeded[label]) continue;
        const ComponentStats& component = components.components()[label];
        const int pixels = static_cast<int>(component.area);
        const unsigned touched = innerSidesTouched(component.bbox + core.tl(), core, image);
        // A region already larger than max_area is dropped whatever lies outside.
        if (touched && pixels <= params_.max_area) grow |= touched;
        if (pixels >= params_.min_area && pixels <= params_.max_area)
          s.found.push_back({c, static_cast<int>(label)});
      }
      stats.regions_ms += msSince(since);
    }
    if (grow != 0) {
      area.core = grownOnSides(core, grow, tile, image);
      mergeOverlapping(s.areas);
      continue;
    }
    for (const auto& [c, label] : s.found) {
      const RunLengthComponents& components = s.components[static_cast<std::size_t>(c)];
      const ComponentStats& component = components.components()[static_cast<std::size_t>(label)];
      if (mosaic && quadsWithAgreeingGreens(frame, components.runsBegin(label), components.runsEnd(label),
                                            core.tl()) < params_.min_agreeing_green_share * component.area) {
        ++stats.fringes[static_cast<std::size_t>(c)];
        continue;
      }
      Region r;
      r.color = static_cast<ColorClass>(c);
      r.area = component.area;
      r.bbox = component.bbox + core.tl();
      const bool weighted = params_.coverage_weighted_moments &&
                            coverageMoments(frame, components.runsBegin(label), components.runsEnd(label),
                                            core.tl(), image, s.coverage, r);
      if (!weighted) writeBinaryMoments(component, core.tl(), r);
      area.regions.push_back(r);
    }
    area.done = true;
    stats.regions_ms += msSince(since);
  }

  // 4. Collect; the cap keeps the largest regions of each class.
  for (const Area& a : s.areas) regions.insert(regions.end(), a.regions.begin(), a.regions.end());
  std::sort(regions.begin(), regions.end(), [](const Region& a, const Region& b) {
    if (a.color != b.color) return a.color < b.color;
    if (a.area != b.area) return a.area > b.area;
    if (a.bbox.y != b.bbox.y) return a.bbox.y < b.bbox.y;
    return a.bbox.x < b.bbox.x;
  });
  std::size_t kept = 0;
  std::array<int, kNumColorClasses> per_class{};
  for (const Region& r : regions) {
    const int c = static_cast<int>(r.color);
    if (per_class[c] < params_.max_regions_per_class) {
      ++per_class[c];
      regions[kept++] = r;
    } else {
      ++stats.cap_hits[c];
    }
  }
  regions.resize(kept);
  stats.regions_ms += msSince(since);
}

}  // namespace soccer_vision
