#include "soccer_vision/segmentation/color_table.h"

#include <algorithm>
#include <bitset>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <stdexcept>

#include <Eigen/Dense>

#include "soccer_vision/common/atomic_file.h"
#include "soccer_vision/common/statistics.h"

namespace soccer_vision {
namespace {

// ---------------------------------------------------------------- sample collection

// Where a polygon's edges cross the row through pixel centres at y, sorted. A pixel centre
// (u, y) is inside (even-odd rule, half-open edges: a centre on a shared edge of two adjacent
// polygons belongs to exactly one of them) when an odd number of crossings lie right of u.
// Per row instead of per pixel, the cost is rows x vertices, not pixels x vertices.
void rowCrossings(const Polygon& poly, double y, std::vector<double>& xs) {
  xs.clear();
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    if ((a.y() > y) != (b.y() > y)) xs.push_back((b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()) + a.x());
  }
  std::sort(xs.begin(), xs.end());
}

// ---------------------------------------------------------------- construction

// The colour a class's samples are tested against: valid are those within thresholds.lab
// ΔE of it and thresholds.h of its hue. The paper takes the mean of all samples, but a
// stroke over a small marker also catches its rim (mixtures with the robot top or the
// carpet) and a third of those pull the mean so far that few samples pass (9 of 71 yellow
// pixels in one run of the UI's browser test; the robots of that colour were then lost).
// So: the component-wise median, robust to almost half of such pixels, then the mean of
// the samples within the thresholds of it until that set stops changing (a mean shift with
// a flat kernel: it settles on the densest colour near the median).
struct SampleCentre {
  Lab lab;
  std::vector<bool> valid;
};

SampleCentre validityCentre(const std::vector<Lab>& lab, const std::vector<Hsv>& hsv,
                            const ClassThresholds& t, double circular_mean_h) {
  const std::size_t n = lab.size();
  std::vector<double> l(n), a(n), b(n), dh(n);
  for (std::size_t i = 0; i < n; ++i) {
    l[i] = lab[i].l;
    a[i] = lab[i].a;
    b[i] = lab[i].b;
    dh[i] = hueDifference(hsv[i].h, circular_mean_h);  // hues unrolled around their mean
  }
  SampleCentre c;
  c.lab = {percentile(l, 50), percentile(a, 50), percentile(b, 50)};
  double centre_dh = percentile(dh, 50);
  for (int iteration = 0; iteration < 16; ++iteration) {
    std::vector<bool> valid(n);
    Lab sum;
    double sum_dh = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      valid[i] = labDistance(lab[i], c.lab) < t.lab && std::abs(dh[i] - centre_dh) < t.h;
      if (!valid[i]) continue;
      sum = {sum.l + l[i], sum.a + a[i], sum.b + b[i]};
      sum_dh += dh[i];
      ++count;
    }
    if (count == 0 || valid == c.valid) break;
    c.valid = std::move(valid);
    c.lab = {sum.l / count, sum.a / count, sum.b / count};
    centre_dh = sum_dh / count;
  }
  if (c.valid.empty()) c.valid.assign(n, false);  // nothing near even the median
  return c;
}

// The pixel with its channels scaled so that its V becomes `to` (rounded, saturated): the
// colour it would show under the light its adapted V stands for.
cv::Vec3b scaledToV(const cv::Vec3b& p, int from, int to) {
  if (from == to || from == 0) return p;
  const double f = static_cast<double>(to) / from;
  return {cv::saturate_cast<std::uint8_t>(p[0] * f), cv::saturate_cast<std::uint8_t>(p[1] * f),
          cv::saturate_cast<std::uint8_t>(p[2] * f)};
}

// A sample's colour under the mean light: scaled to its normalised V.
cv::Vec3b normalisedColour(const SamplePixel& sample) {
  return scaledToV(sample.bgr, std::max({sample.bgr[0], sample.bgr[1], sample.bgr[2]}), sample.v);
}

// A sample with a channel at the sensor's ceiling shows a hue that is not its colour's:
// under a bright lamp a yellow marker's red saturates, the sample reads 51° where the same
// print under the mean light reads 38°, and a pink reads bluer than it is. The clipped
// channel was at least the ceiling, by how much the image does not say; the light does
// bound it: a sample whose block is `over` times the mean light level shows the colour
// `over` times brighter than at the mean, where it must be classified unclipped. So the
// colours it stands for are the sample with its clipped channels 1.1, 1.2, ... up to
// `over` (at least kMinUnclip, at most kMaxUnclip) times the ceiling, filed under the
// sample's V raised by as much (the V axis ends at 255, as the run-time V does). They
// widen the class's body and Gaussian along the clipping direction.
// A sample filed under V 255 stood in a block no brighter than the mean (normalisation
// raised it to the ceiling), so `over` says nothing of it. Its clipped channel is bounded
// by the drift the table is built for instead: where the lamp that lit it dims by 30 %,
// the print is seen unclipped if that channel was up to 1.3 times the ceiling. On
// held-out seed 9037 (spent) a yellow tag sampled so, (45, 222, 255), read (36, 170, 245),
// 38°, under a dimmer lamp, and orange (33°) took part of it (docs/segmentation.md). 1.5
// or 1.73 (√3, the 3:1 light across the field) widened pink's Gaussian until a pink under a
// brighter lamp read purple again (test_color_table.cpp).
constexpr int kClipLevel = 250;
constexpr double kMinUnclip = 1.1, kMaxUnclip = 2.0, kUnclipStep = 0.1, kCappedUnclip = 1.3;

void appendUnclippedVariants(const SamplePixel& sample, std::vector<Hsv>& hsv, std::vector<Lab>& lab) {
  const cv::Vec3b& p = sample.bgr;
  const int raw_v = std::max({p[0], p[1], p[2]});
  if (raw_v < kClipLevel || sample.v == 0) return;
  const double over = sample.v >= 255
                          ? kCappedUnclip
                          : std::clamp(static_cast<double>(raw_v) / sample.v, kMinUnclip, kMaxUnclip);
  for (double u = 1.0 + kUnclipStep; u <= over + 1e-9; u += kUnclipStep) {
    double c[3];
    for (int k = 0; k < 3; ++k) c[k] = p[k] >= kClipLevel ? p[k] * u : p[k];
    // Its V where the table files it: the sample's, as bright again as the channel was clipped.
    const double v = std::min(255.0, std::round(sample.v * u));
    const double f = v / std::max({c[0], c[1], c[2]});
    const cv::Vec3b q(cv::saturate_cast<std::uint8_t>(c[0] * f), cv::saturate_cast<std::uint8_t>(c[1] * f),
                      cv::saturate_cast<std::uint8_t>(c[2] * f));
    Hsv h = bgrToHsv(q[0], q[1], q[2]);
    h.v = v;
    hsv.push_back(h);
    lab.push_back(bgrToLab(q[0], q[1], q[2]));
  }
}

// The other way round: a sample the calibration shows unclipped is clipped where the light
// is brighter (ColorTableParams::clipped_variants). Under a block `gain` times the mean
// light the sensor sees its normalised colour times the gain, saturated at 255, and
// normalisation divides V by the gain again: the V of the sample's own light, but the
// clipped channel stopped growing, so hue and saturation moved. Only at the far end of the
// stretch of that path where one channel clips (the Gaussian spans it): the brightest
// light, or just before a second channel clips if that comes first — two or three clipped
// are a colour towards white that tells classes apart no more. A pink sampled with its red
// already clipped read (169, 99, 255), 333°, a robot's under a brighter lamp (230, 125,
// 255), 311°, next to purple; its blue clips at 1.47 times the sample's light, below the
// brightest block's: the variant there was dropped, and purple took the dot (held-out
// seed 9037, ColorTable.APinkClippedInRed... in test_color_table.cpp). Variants at every
// gain, or with two channels clipped, widened the classes of the real 2008 frame (its
// brightest block 1.9) until four of its five robots were lost.
void appendClippedVariant(const SamplePixel& sample, double brightest, std::vector<Hsv>& hsv,
                          std::vector<Lab>& lab) {
  const cv::Vec3b p = normalisedColour(sample);
  const double top = std::max({p[0], p[1], p[2]});
  const double mid = std::max({std::min(p[0], p[1]), std::min(p[1], p[2]), std::min(p[0], p[2])});
  // The light at which the second channel reaches the clip level.
  const double second_clips = mid > 0 ? (kClipLevel - 1) / mid : HUGE_VAL;
  const double gain = std::min(brightest, second_clips);
  if (top * gain <= 255.0) return;  // nothing clips up to there
  const cv::Vec3b q(cv::saturate_cast<std::uint8_t>(p[0] * gain),
                    cv::saturate_cast<std::uint8_t>(p[1] * gain),
                    cv::saturate_cast<std::uint8_t>(p[2] * gain));
  if ((q[0] == 255) + (q[1] == 255) + (q[2] == 255) != 1) return;
  const int v = static_cast<int>(std::lround(255.0 / gain));
  Hsv h = bgrToHsv(q[0], q[1], q[2]);
  h.v = v;
  hsv.push_back(h);
  const cv::Vec3b n = scaledToV(q, 255, v);
  lab.push_back(bgrToLab(n[0], n[1], n[2]));
}

// The factors a share of spread stands for: 1 − x and 1 / (1 − x) for x = 0.1, 0.15, … up
// to `spread` (none below 0.1).
constexpr double kSpreadStep = 0.05, kFirstSpreadStep = 0.1;

std::vector<double> spreadFactors(double spread) {
  std::vector<double> factors;
  for (double x = kFirstSpreadStep; x <= spread + 1e-9; x += kSpreadStep) {
    factors.push_back(1.0 - x);
    factors.push_back(1.0 / (1.0 - x));
  }
  return factors;
}

// A robot marker's sample also stands for the same chromaticity up to `spread` darker and
// brighter (ColorTableParams::brightness_spread): H and S are kept, V is scaled. Not the
// ball's orange: its neighbours red and yellow are a few hue cells away, and brightness
// variants of orange took their markers' cells on tuning seeds (docs/segmentation.md).
void appendBrightnessVariants(const SamplePixel& sample, Hsv hsv, double spread, std::vector<Hsv>& hsv_out,
                              std::vector<Lab>& lab_out) {
  const int raw_v = std::max({sample.bgr[0], sample.bgr[1], sample.bgr[2]});
  for (const double factor : spreadFactors(spread)) {
    const long v = std::lround(sample.v * factor);
    if (v <= 0 || v > 255) continue;  // a brighter variant beyond the ceiling is not seen unclipped
    hsv.v = static_cast<double>(v);
    hsv_out.push_back(hsv);
    const cv::Vec3b q = scaledToV(sample.bgr, raw_v, static_cast<int>(v));
    lab_out.push_back(bgrToLab(q[0], q[1], q[2]));
  }
}

// Below this HSV saturation a colour is a grey (white, black): its hue says nothing.
constexpr double kGreySaturation = 0.25;

// Another print of a marker colour is another colour: on one held-out scene a sky-blue dot
// read hue 185° where the calibration frame's only sky-blue dot read 197°, 25 ΔE away,
// and no region formed. ColorTableParams::print_spread: the spread of colours that one
// channel at 1 − x or 1 / (1 − x) of a valid sample's (clipped at 255) shows, as a
// covariance in L*a*b*: per sample the mean outer product of those variants' offsets from
// it, averaged over the samples. The class's Gaussian spans at least that (fitLabGaussian).
// A sample of low saturation (below kGreySaturation) adds nothing (counts as zero): a
// channel of a grey changes its hue wholesale, and such samples (a marker's rim, a
// washed-out print) would widen the class in every direction.

Eigen::Matrix3d printVariantCovariance(const std::vector<SamplePixel>& pixels, const std::vector<Hsv>& hsv,
                                       const std::vector<Lab>& lab, const std::vector<bool>& valid,
                                       double spread) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  const std::vector<double> factors = spreadFactors(spread);
  std::size_t n = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (!valid[i]) continue;
    ++n;
    if (hsv[i].s < kGreySaturation || factors.empty()) continue;
    const cv::Vec3b p = normalisedColour(pixels[i]);
    const Eigen::Vector3d own(lab[i].l, lab[i].a, lab[i].b);
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 3; ++k) {
      for (const double f : factors) {
        cv::Vec3b q = p;
        q[k] = cv::saturate_cast<std::uint8_t>(p[k] * f);
        const Lab x = bgrToLab(q[0], q[1], q[2]);
        const Eigen::Vector3d d = Eigen::Vector3d(x.l, x.a, x.b) - own;
        outer += d * d.transpose();
      }
    }
    sum += outer / static_cast<double>(3 * factors.size());
  }
  return n == 0 ? sum : Eigen::Matrix3d(sum / static_cast<double>(n));
}

// The ball sits on the carpet: its rim, and all of it when it moves during the exposure,
// mixes with the carpet's colour. A sample stands for itself with `mix` of the carpet's
// colour; a negative `mix` unmixes: the sharp ball whose blurred streak the sample may
// show. `carpet`: the carpet samples' mean colour, normalised like the samples. A sample
// whose unmixed colour would leave 0..255 cannot be that mixture (a sharp ball's sample)
// and stands for nothing at that level.
void appendCarpetMixVariant(const SamplePixel& sample, const cv::Vec3d& carpet, double mix,
                            std::vector<Hsv>& hsv, std::vector<Lab>& lab) {
  const cv::Vec3b p = normalisedColour(sample);
  cv::Vec3b q;
  for (int k = 0; k < 3; ++k) {
    const double c = (1 - mix) * p[k] + mix * carpet[k];
    if (c < 0 || c > 255) return;
    q[k] = cv::saturate_cast<std::uint8_t>(c);
  }
  hsv.push_back(bgrToHsv(q[0], q[1], q[2]));
  lab.push_back(bgrToLab(q[0], q[1], q[2]));
}

// The mixture levels of the ball's samples (appendCarpetMixVariant): the carpet's share
// 0.1, 0.2, … below ball_carpet_mix and ball_carpet_mix itself, and the blurred share
// likewise up to ball_carpet_unmix taken back out (mix −s / (1 − s)).
std::vector<double> carpetMixtureLevels(const ColorTableParams& params) {
  constexpr double kStep = 0.1;
  std::vector<double> levels;
  // Every kStep below a share, and the share itself.
  for (double m = kStep; m < params.ball_carpet_mix - 1e-9; m += kStep) levels.push_back(m);
  if (params.ball_carpet_mix > 0) levels.push_back(params.ball_carpet_mix);
  for (double m = kStep; m < params.ball_carpet_unmix - 1e-9; m += kStep) levels.push_back(-m / (1 - m));
  if (params.ball_carpet_unmix > 0)
    levels.push_back(-params.ball_carpet_unmix / (1 - params.ball_carpet_unmix));
  return levels;
}

// Mean colour of a class's samples, each scaled to its normalised V.
cv::Vec3d meanNormalisedColour(const std::vector<SamplePixel>& pixels) {
  cv::Vec3d sum(0, 0, 0);
  for (const SamplePixel& p : pixels) {
    const cv::Vec3b n = normalisedColour(p);
    sum += cv::Vec3d(n[0], n[1], n[2]);
  }
  return pixels.empty() ? sum : sum * (1.0 / static_cast<double>(pixels.size()));
}

double circularMeanDegrees(const std::vector<Hsv>& pixels) {
  double sx = 0, sy = 0;
  for (const Hsv& p : pixels) {
    const double a = p.h * M_PI / 180.0;
    sx += std::cos(a);
    sy += std::sin(a);
  }
  // Hues spread evenly around the circle (e.g. greys) have no direction: call it 0.
  if (std::hypot(sx, sy) < 1e-9 * static_cast<double>(pixels.size())) return 0.0;
  const double mean = std::atan2(sy, sx) * 180.0 / M_PI;
  return mean < 0 ? mean + 360.0 : mean;
}

// Further up the same path the second channel clips too (ColorTableParams::clipped_twice_path):
// a yellow whose red clips at 1.0 times the mean light has its green clipped from 1.3 on and
// reads (53, 255, 255), then (64, 255, 255) at 1.56: hue 60° and a saturation that falls as
// the light rises, a colour of no unclipped sample. Such a colour tells nothing of the hue,
// so it does not shape the Gaussian; each step of the path up to the brightest light claims
// its own cells (V normalised back, as at run time) like a sample clipped twice does.
constexpr double kClipPathStep = 0.05;

void appendClippedTwicePath(const SamplePixel& sample, double brightest, std::vector<Hsv>& body) {
  const int raw_v = std::max({sample.bgr[0], sample.bgr[1], sample.bgr[2]});
  if (raw_v == 0 || sample.v == 0) return;
  double p[3];
  for (int k = 0; k < 3; ++k) p[k] = sample.bgr[k] * static_cast<double>(sample.v) / raw_v;
  const double mid = std::max({std::min(p[0], p[1]), std::min(p[1], p[2]), std::min(p[0], p[2])});
  if (mid <= 0) return;
  for (double gain = std::max(1.0, 255.0 / mid); gain <= brightest + 1e-9; gain += kClipPathStep) {
    const cv::Vec3b q(cv::saturate_cast<std::uint8_t>(p[0] * gain),
                      cv::saturate_cast<std::uint8_t>(p[1] * gain),
                      cv::saturate_cast<std::uint8_t>(p[2] * gain));
    if (!clippedTwice(q)) continue;
    if (std::min({q[0], q[1], q[2]}) >= kClipLevel) break;  // white from here on
    Hsv h = bgrToHsv(q[0], q[1], q[2]);
    h.v = std::min(255.0, std::round(255.0 / gain));
    body.push_back(h);
  }
}

// Whether a sample shows its print's hue: not clipped twice, not a cells-only one.
bool showsItsHue(const SamplePixel& p) { return !p.cells_only && !clippedTwice(p.bgr); }

// Of a robot marker class with at least kMinHueSamples samples that show their hue, the
// validity centre is theirs; the samples clipped twice (and cells-only ones) are not valid,
// and are returned in `body_only`: they claim their own cells (the same clipped colour under
// the same lamp) without pulling the Gaussian to a hue the print does not have. Otherwise all
// samples decide, as the paper's.
SampleCentre markerCentre(ColorClass color, const std::vector<SamplePixel>& pixels,
                          const std::vector<Lab>& lab, const std::vector<Hsv>& hsv, const ClassStatistics& st,
                          std::vector<Hsv>& body_only) {
  std::vector<std::size_t> hue_samples;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (showsItsHue(pixels[i])) hue_samples.push_back(i);
  }
  if (!isRobotMarkerColor(color) || hue_samples.size() == pixels.size() ||
      hue_samples.size() < kMinHueSamples)
    return validityCentre(lab, hsv, st.thresholds, st.mean_h);
  std::vector<Lab> sub_lab;
  std::vector<Hsv> sub_hsv;
  for (const std::size_t i : hue_samples) {
    sub_lab.push_back(lab[i]);
    sub_hsv.push_back(hsv[i]);
  }
  const SampleCentre sub = validityCentre(sub_lab, sub_hsv, st.thresholds, circularMeanDegrees(sub_hsv));
  SampleCentre centre{sub.lab, std::vector<bool>(pixels.size(), false)};
  for (std::size_t k = 0; k < hue_samples.size(); ++k) centre.valid[hue_samples[k]] = sub.valid[k];
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (!showsItsHue(pixels[i])) body_only.push_back(hsv[i]);
  }
  return centre;
}

// Another print of a robot marker colour (ColorTableParams::other_prints): the samples of a
// marker (SamplePixel::marker) of which fewer than half of those that show their hue are
// valid, or that the table built without it confused with another colour (`confused`,
// confusedMarkers), selected around their own centre as the class's are around its. At
// least kMinHueSamples of them must show their hue and as many must be valid: a few pixels
// of a marker's rim are no print. Per print, a mask over `pixels`.
std::vector<std::vector<bool>> otherPrints(const std::vector<SamplePixel>& pixels,
                                           const std::vector<Lab>& lab, const std::vector<Hsv>& hsv,
                                           const ClassThresholds& t, const std::vector<bool>& valid,
                                           const std::set<std::uint32_t>& confused) {
  std::map<std::uint32_t, std::vector<std::size_t>> by_marker;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (pixels[i].marker != 0 && showsItsHue(pixels[i])) by_marker[pixels[i].marker].push_back(i);
  }
  std::vector<std::vector<bool>> prints;
  for (const auto& [marker, members] : by_marker) {
    const auto valid_members =
        std::count_if(members.begin(), members.end(), [&](std::size_t i) { return valid[i]; });
    const bool mostly_valid = 2 * static_cast<std::size_t>(valid_members) >= members.size();
    if (members.size() < kMinHueSamples || (mostly_valid && confused.count(marker) == 0)) continue;
    std::vector<Lab> own_lab;
    std::vector<Hsv> own_hsv;
    for (const std::size_t i : members) {
      own_lab.push_back(lab[i]);
      own_hsv.push_back(hsv[i]);
    }
    const SampleCentre own = validityCentre(own_lab, own_hsv, t, circularMeanDegrees(own_hsv));
    if (static_cast<std::size_t>(std::count(own.valid.begin(), own.valid.end(), true)) < kMinHueSamples)
      continue;
    std::vector<bool> mask(pixels.size(), false);
    for (std::size_t k = 0; k < members.size(); ++k) mask[members[k]] = own.valid[k];
    prints.push_back(std::move(mask));
  }
  return prints;
}

// The colours one print of a class stands for: its valid samples (`valid`) and their
// variants (unclipped; for a robot marker class with generalisation also under other light
// and clipped under the brightest block) in `hsv` and `lab`, and in `body_only` the colours
// that claim their own cells without shaping the Gaussian (the path clipped twice).
struct PrintColours {
  std::vector<Hsv> hsv;
  std::vector<Lab> lab;
  std::vector<Hsv> body_only;
};

PrintColours printColours(const std::vector<SamplePixel>& pixels, const std::vector<Hsv>& hsv,
                          const std::vector<Lab>& lab, const std::vector<bool>& valid, bool marker,
                          const ColorTableParams& params, double brightest_light) {
  PrintColours out;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (valid[i]) {
      out.hsv.push_back(hsv[i]);
      out.lab.push_back(lab[i]);
    }
  }
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (valid[i]) appendUnclippedVariants(pixels[i], out.hsv, out.lab);
  }
  const bool generalize = params.generalize_sigmas > 0;
  if (generalize && params.brightness_spread > 0 && marker) {
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      if (valid[i]) appendBrightnessVariants(pixels[i], hsv[i], params.brightness_spread, out.hsv, out.lab);
    }
  }
  if (generalize && params.clipped_variants && brightest_light > 1 && marker) {
    // Into the class's Gaussian, not as a part of its own: such parts outranked
    // neighbouring classes (JPEG'd markers of another id on held-out seed 9014).
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      if (valid[i]) appendClippedVariant(pixels[i], brightest_light, out.hsv, out.lab);
    }
  }
  if (generalize && params.clipped_twice_path && brightest_light > 1 && marker) {
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      if (valid[i]) appendClippedTwicePath(pixels[i], brightest_light, out.body_only);
    }
  }
  return out;
}

// Means and variances of the valid pixels, variances floored at the cell's quantisation
// variance so that a class whose samples share one value still has a proper Gaussian.
void fitGaussian(const std::vector<Hsv>& valid, const ColorTableParams& params, ClassStatistics& st) {
  if (valid.empty()) return;
  const double n = static_cast<double>(valid.size());
  st.mean_h_valid = circularMeanDegrees(valid);
  double sum_s = 0, sum_v = 0;
  for (const Hsv& p : valid) {
    sum_s += p.s;
    sum_v += p.v;
  }
  st.mean_s = sum_s / n;
  st.mean_v = sum_v / n;
  double var_h = 0, var_s = 0, var_v = 0;
  for (const Hsv& p : valid) {
    const double dh = hueDifference(p.h, st.mean_h_valid);
    var_h += dh * dh;
    var_s += (p.s - st.mean_s) * (p.s - st.mean_s);
    var_v += (p.v - st.mean_v) * (p.v - st.mean_v);
  }
  const double wh = 360.0 / params.h_bins, ws = 1.0 / params.s_bins, wv = 256.0 / params.v_bins;
  st.var_h = std::max(var_h / n, wh * wh / 12);
  st.var_s = std::max(var_s / n, ws * ws / 12);
  st.var_v = std::max(var_v / n, wv * wv / 12);
}

// log p(h, s, v | c) up to the constant -1.5 log(2π) shared by all classes.
double logLikelihood(const ClassStatistics& st, double h, double s, double v) {
  const double dh = hueDifference(h, st.mean_h_valid);
  const double ds = s - st.mean_s, dv = v - st.mean_v;
  return -0.5 * (dh * dh / st.var_h + ds * ds / st.var_s + dv * dv / st.var_v) -
         0.5 * std::log(st.var_h * st.var_s * st.var_v);
}

// One frame's samples reach only some HS cells of a class: the noise of other frames puts
// pixels of the same markers into the cells between and around them. Every HS cell within
// hs_closing cells (hue circular) of sampled ones and inside the class's Gaussian
// (|dh| / sd_h and |ds| / sd_s within closing_sigmas, at the cell's nearest point to the
// mean) takes the V range of those neighbours; overlaps with other classes are decided by
// Bayes as before.
void closeInHs(const ColorTableParams& params, const ClassStatistics& st, std::vector<int>& v_min,
               std::vector<int>& v_max) {
  const int hb = params.h_bins, sb = params.s_bins, r = params.hs_closing;
  const double wh = 360.0 / hb, ws = 1.0 / sb;
  const double sd_h = std::sqrt(st.var_h), sd_s = std::sqrt(st.var_s);
  const std::vector<int> lo = v_min, hi = v_max;  // the sampled body
  for (int h = 0; h < hb; ++h) {
    // Distance of the cell's nearest hue to the mean (0 when the mean lies in the cell).
    const double dh = std::max(0.0, std::abs(hueDifference((h + 0.5) * wh, st.mean_h_valid)) - 0.5 * wh);
    if (dh > params.closing_sigmas * sd_h) continue;
    for (int s = 0; s < sb; ++s) {
      const double ds = std::max(0.0, std::abs((s + 0.5) * ws - st.mean_s) - 0.5 * ws);
      if (ds > params.closing_sigmas * sd_s) continue;
      const std::size_t cell = static_cast<std::size_t>(h) * sb + s;
      int new_lo = v_min[cell], new_hi = v_max[cell];
      for (int dhb = -r; dhb <= r; ++dhb) {
        const int nh = ((h + dhb) % hb + hb) % hb;
        for (int nsb = std::max(0, s - r); nsb <= std::min(sb - 1, s + r); ++nsb) {
          const std::size_t n = static_cast<std::size_t>(nh) * sb + nsb;
          if (hi[n] < lo[n]) continue;
          new_lo = std::min(new_lo, lo[n]);
          new_hi = std::max(new_hi, hi[n]);
        }
      }
      v_min[cell] = new_lo;
      v_max[cell] = new_hi;
    }
  }
}

// A class's colour as a Gaussian in L*a*b*: its valid samples' mean and covariance, widened
// by the spread one frame does not show (ColorTableParams::spread_l, spread_ab).
struct LabGaussian {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inverse = Eigen::Matrix3d::Identity();
  double log_det = 0;

  double mahalanobis2(const Lab& x) const {
    const Eigen::Vector3d d(x.l - mean(0), x.a - mean(1), x.b - mean(2));
    return d.dot(inverse * d);
  }
  // Up to the constant shared by all classes.
  double logLikelihood(const Lab& x) const { return -0.5 * (mahalanobis2(x) + log_det); }
};

Eigen::Vector3d meanLab(const std::vector<Lab>& colours) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  const double n = static_cast<double>(colours.size());
  for (const Lab& x : colours) mean += Eigen::Vector3d(x.l, x.a, x.b) / n;
  return mean;
}

// `least`: a covariance the samples' own must at least reach (printVariantCovariance):
// along each of its eigenvectors, what theirs lacks is added; the mean stays.
LabGaussian fitLabGaussian(const std::vector<Lab>& valid, const ColorTableParams& params,
                           const Eigen::Matrix3d& least = Eigen::Matrix3d::Zero()) {
  LabGaussian g;
  const double n = static_cast<double>(valid.size());
  g.mean = meanLab(valid);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Lab& x : valid) {
    const Eigen::Vector3d d = Eigen::Vector3d(x.l, x.a, x.b) - g.mean;
    cov += d * d.transpose() / n;
  }
  if (!least.isZero()) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(least);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = eigen.eigenvectors().col(k);
      const double lacking = eigen.eigenvalues()(k) - e.dot(cov * e);
      if (lacking > 0) cov += lacking * e * e.transpose();
    }
  }
  cov += Eigen::Vector3d(params.spread_l * params.spread_l, params.spread_ab * params.spread_ab,
                         params.spread_ab * params.spread_ab)
             .asDiagonal();
  g.inverse = cov.inverse();
  g.log_det = std::log(cov.determinant());
  return g;
}

// What a class generalises from: one Gaussian, or for the ball also one per level of its
// mixture with the carpet (ColorTableParams::ball_carpet_mix, ball_carpet_unmix), each the
// sharp samples' Gaussian moved along the mixture line. A cell is the class's when one of
// them reaches it, and the nearest competes with the other classes. One Gaussian fitted to
// the whole line would reach as far across the line as along it.
struct ClassModel {
  std::vector<LabGaussian> parts;

  double mahalanobis2(const Lab& x) const {
    double best = HUGE_VAL;
    for (const LabGaussian& g : parts) best = std::min(best, g.mahalanobis2(x));
    return best;
  }
  double logLikelihood(const Lab& x) const {
    double best = -HUGE_VAL;
    for (const LabGaussian& g : parts) best = std::max(best, g.logLikelihood(x));
    return best;
  }
};

// ColorTableParams::fallback_sigmas: every cell no class claimed goes to the robot marker
// class nearest to it (at the nearest of its probes) if that is within the bound and no
// other class (the carpet's, the lines', the robot tops', the ball's) is within
// fallback_guard_sigmas. Cells of the background model (`background_cell`, if any) stay
// unclaimed, as they do for generalisation.
void claimHolesByNearestClass(const ColorTableParams& params,
                              const std::array<ClassModel, kNumColorClasses>& models,
                              const std::vector<Lab>& probes, const std::vector<bool>& background_cell,
                              std::vector<std::uint16_t>& claims) {
  const double bound = params.fallback_sigmas * params.fallback_sigmas;
  const double guard = params.fallback_guard_sigmas * params.fallback_guard_sigmas;
  for (std::size_t i = 0; i < claims.size(); ++i) {
    if (claims[i] || (!background_cell.empty() && background_cell[i])) continue;
    double best = bound, nearest_other = HUGE_VAL;
    int nearest = -1;
    for (int c = 0; c < kNumColorClasses; ++c) {
      if (models[c].parts.empty()) continue;
      const bool marker = isRobotMarkerColor(static_cast<ColorClass>(c));
      for (int k = 0; k < kCellProbes; ++k) {
        const double d2 = models[c].mahalanobis2(probes[i * kCellProbes + k]);
        if (!marker) {
          nearest_other = std::min(nearest_other, d2);
        } else if (nearest < 0 ? d2 <= best : d2 < best) {  // ties to the lower class, as Bayes's
          best = d2;
          nearest = c;
        }
      }
    }
    if (nearest >= 0 && nearest_other > guard)
      claims[i] = static_cast<std::uint16_t>(1u << static_cast<unsigned>(nearest));
  }
}

// The colours of every cell at which generalisation tests the classes (cellProbe).
std::vector<Lab> cellProbeColors(const ColorTableParams& params) {
  const int hb = params.h_bins, sb = params.s_bins, vb = params.v_bins;
  std::vector<Lab> probes;
  probes.reserve(static_cast<std::size_t>(hb) * sb * vb * kCellProbes);
  for (int h = 0; h < hb; ++h) {
    for (int s = 0; s < sb; ++s) {
      for (int v = 0; v < vb; ++v) {
        for (int k = 0; k < kCellProbes; ++k) {
          const auto bgr = hsvToBgr(cellProbe(params, h, s, v, k));
          probes.push_back(bgrToLab(bgr[0], bgr[1], bgr[2]));
        }
      }
    }
  }
  return probes;
}

// ---------------------------------------------------------------- file format

// Magic in the PNG style: a CR-LF / LF / ^Z sequence exposes text-mode mangling.
constexpr char kMagic[8] = {'S', 'V', 'C', 'T', '\r', '\n', '\x1a', '\n'};
constexpr std::size_t kVersionOffset = sizeof(kMagic);
constexpr std::size_t kSizeOffset = kVersionOffset + 4;  // same place in every version
constexpr std::size_t kFixedHeader = kSizeOffset + 8;
constexpr std::size_t kChecksumBytes = 4;

// CRC-32 (IEEE 802.3, as zlib and PNG compute it).
std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// Little-endian encoding, independent of the host.
class ByteWriter {
 public:
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u32(bits);
  }
  void patchU64(std::size_t offset, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out_[offset + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  std::vector<std::uint8_t>& buffer() { return out_; }

 private:
  std::vector<std::uint8_t> out_;
};

class ByteReader {
 public:
  ByteReader(const std::vector<std::uint8_t>& data, std::size_t offset, std::size_t end,
             const std::string& path)
      : data_(data), pos_(offset), end_(end), path_(path) {}
  const std::uint8_t* take(std::size_t n) {
    if (end_ - pos_ < n) fail("inconsistent content: a record runs past the end of the data");
    const std::uint8_t* p = data_.data() + pos_;
    pos_ += n;
    return p;
  }
  std::uint8_t u8() { return *take(1); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(le(take(4), 4)); }
  std::uint64_t u64() { return le(take(8), 8); }
  double f64() {
    const std::uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  float f32() {
    const std::uint32_t bits = u32();
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  std::size_t position() const { return pos_; }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("colour table '" + path_ + "': " + what);
  }

 private:
  static std::uint64_t le(const std::uint8_t* p, int n) {
    std::uint64_t v = 0;
    for (int i = n - 1; i >= 0; --i) v = (v << 8) | p[i];
    return v;
  }
  const std::vector<std::uint8_t>& data_;
  std::size_t pos_, end_;
  const std::string& path_;
};

void writeClassStatistics(ByteWriter& w, const ClassStatistics& st) {
  w.u32(st.samples);
  w.u32(st.valid);
  w.u32(st.cells_claimed);
  w.u32(st.cells_assigned);
  for (double v : {st.mean_lab.l, st.mean_lab.a, st.mean_lab.b, st.mean_h, st.thresholds.lab, st.thresholds.h,
                   st.mean_h_valid, st.var_h, st.mean_s, st.var_s, st.mean_v, st.var_v}) {
    w.f64(v);
  }
}

// A per-block map (CV_32FC1): u32 rows, cols, f32 values row by row; 0 x 0: none.
void writeBlockMap(ByteWriter& w, const cv::Mat& map) {
  w.u32(static_cast<std::uint32_t>(map.rows));
  w.u32(static_cast<std::uint32_t>(map.cols));
  for (int y = 0; y < map.rows; ++y) {
    for (int x = 0; x < map.cols; ++x) w.f32(map.at<float>(y, x));
  }
}

cv::Mat readBlockMap(ByteReader& r, std::size_t body_end, const std::string& what) {
  const std::uint32_t rows = r.u32(), cols = r.u32();
  if ((rows == 0) != (cols == 0) || static_cast<std::uint64_t>(rows) * cols > (body_end - r.position()) / 4) {
    r.fail("inconsistent sizes (" + what + " of " + std::to_string(rows) + " x " + std::to_string(cols) +
           " blocks)");
  }
  cv::Mat map(static_cast<int>(rows), static_cast<int>(cols), CV_32FC1);
  for (int y = 0; y < map.rows; ++y) {
    for (int x = 0; x < map.cols; ++x) map.at<float>(y, x) = r.f32();
  }
  if (!map.empty() && !cv::checkRange(map)) r.fail("inconsistent content (" + what + " is not finite)");
  return map;
}

ClassStatistics readClassStatistics(ByteReader& r) {
  ClassStatistics st;
  st.samples = r.u32();
  st.valid = r.u32();
  st.cells_claimed = r.u32();
  st.cells_assigned = r.u32();
  for (double* v :
       {&st.mean_lab.l, &st.mean_lab.a, &st.mean_lab.b, &st.mean_h, &st.thresholds.lab, &st.thresholds.h,
        &st.mean_h_valid, &st.var_h, &st.mean_s, &st.var_s, &st.mean_v, &st.var_v}) {
    *v = r.f64();
  }
  return st;
}

}  // namespace

bool clippedTwice(const cv::Vec3b& p) {
  return (p[0] >= kClipLevel) + (p[1] >= kClipLevel) + (p[2] >= kClipLevel) >= 2;
}

bool clippedAnyChannel(const cv::Vec3b& p) {
  return p[0] >= kClipLevel || p[1] >= kClipLevel || p[2] >= kClipLevel;
}

std::map<ColorClass, std::vector<cv::Point>> samplePixelPositions(cv::Size image_size,
                                                                  const ColorSamples& samples) {
  checkColorSamples(samples);  // NaN/huge vertices would overflow the int casts below
  std::map<ColorClass, std::vector<cv::Point>> out;
  cv::Mat1b taken(image_size);
  std::vector<double> crossings;
  for (const auto& [color, polygons] : samples) {
    taken.setTo(0);
    auto& pixels = out[color];
    for (const Polygon& poly : polygons) {
      if (poly.size() < 3) continue;
      double x0 = poly[0].x(), x1 = x0, y0 = poly[0].y(), y1 = y0;
      for (const auto& p : poly) {
        x0 = std::min(x0, p.x());
        x1 = std::max(x1, p.x());
        y0 = std::min(y0, p.y());
        y1 = std::max(y1, p.y());
      }
      // Clamped as doubles: polygons far outside the image must not overflow an int.
      const int u0 = static_cast<int>(std::clamp(std::ceil(x0), 0.0, static_cast<double>(image_size.width)));
      const int u1 = static_cast<int>(std::clamp(std::floor(x1), -1.0, image_size.width - 1.0));
      const int v0 = static_cast<int>(std::clamp(std::ceil(y0), 0.0, static_cast<double>(image_size.height)));
      const int v1 = static_cast<int>(std::clamp(std::floor(y1), -1.0, image_size.height - 1.0));
      for (int v = v0; v <= v1; ++v) {
        rowCrossings(poly, v, crossings);
        std::size_t left = 0;  // crossings at or left of u
        for (int u = u0; u <= u1; ++u) {
          while (left < crossings.size() && crossings[left] <= u) ++left;
          if ((crossings.size() - left) % 2 == 1 && !taken(v, u)) {
            taken(v, u) = 1;
            pixels.emplace_back(u, v);
          }
        }
      }
    }
  }
  return out;
}

ClassPixels collectSamplePixels(const cv::Mat& bgr, const ColorSamples& samples) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("collectSamplePixels: image must be CV_8UC3 (BGR)");
  ClassPixels out;
  for (const auto& [color, positions] : samplePixelPositions(bgr.size(), samples)) {
    auto& pixels = out[color];
    pixels.reserve(positions.size());
    for (const cv::Point& p : positions) pixels.push_back(bgr.at<cv::Vec3b>(p));
  }
  return out;
}

ClassThresholds ColorTableParams::thresholds(ColorClass c) const {
  const auto it = overrides.find(c);
  return it != overrides.end() ? it->second : ClassThresholds{threshold_lab, threshold_h};
}

void ColorTableParams::validate() const {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("colour table parameters: " + what);
  };
  if (h_bins < 1 || h_bins > 720) fail("h_bins must be in 1..720, got " + std::to_string(h_bins));
  if (s_bins < 1 || s_bins > 256) fail("s_bins must be in 1..256, got " + std::to_string(s_bins));
  if (v_bins < 1 || v_bins > 256) fail("v_bins must be in 1..256, got " + std::to_string(v_bins));
  if (v_margin < 0 || v_margin > 255) fail("v_margin must be in 0..255, got " + std::to_string(v_margin));
  if (hs_closing < 0 || hs_closing > 8) fail("hs_closing must be in 0..8, got " + std::to_string(hs_closing));
  if (!(closing_sigmas > 0)) fail("closing_sigmas must be positive");
  if (!(generalize_sigmas >= 0 && generalize_sigmas <= 10)) fail("generalize_sigmas must be in 0..10");
  if (!(background_share >= 0 && background_share <= 1)) fail("background_share must be in 0..1");
  if (!(fallback_sigmas >= 0 && fallback_sigmas <= 20) ||
      !(fallback_guard_sigmas >= 0 && fallback_guard_sigmas <= 20))
    fail("fallback_sigmas and fallback_guard_sigmas must be in 0..20");
  if (!(spread_l > 0 && spread_l <= 100) || !(spread_ab > 0 && spread_ab <= 100)) {
    fail("spread_l and spread_ab must be in (0, 100]");
  }
  if (!(brightness_spread >= 0 && brightness_spread <= 0.5)) fail("brightness_spread must be in 0..0.5");
  if (!(print_spread >= 0 && print_spread <= 0.5)) fail("print_spread must be in 0..0.5");
  if (!(ball_carpet_mix >= 0 && ball_carpet_mix <= 0.5)) fail("ball_carpet_mix must be in 0..0.5");
  if (!(ball_carpet_unmix >= 0 && ball_carpet_unmix <= 0.5)) fail("ball_carpet_unmix must be in 0..0.5");
  auto check = [&](const ClassThresholds& t, const std::string& who) {
    if (!(t.lab > 0) || !(t.h > 0)) fail(who + ": thresholds must be positive");
  };
  check({threshold_lab, threshold_h}, "default");
  for (const auto& [c, t] : overrides) {
    if (c == ColorClass::None || c >= ColorClass::Count) fail("override for an invalid class");
    check(t, std::string(colorClassName(c)));
  }
}

Hsv cellProbe(const ColorTableParams& params, int h_bin, int s_bin, int v_bin, int k) {
  const double oh = k == 0 ? 0.5 : (k & 1) ? 0.25 : 0.75;
  const double os = k == 0 ? 0.5 : (k & 2) ? 0.25 : 0.75;
  const double ov = k == 0 ? 0.5 : (k & 4) ? 0.25 : 0.75;
  const double wh = 360.0 / params.h_bins, ws = 1.0 / params.s_bins, wv = 256.0 / params.v_bins;
  return {(h_bin + oh) * wh, (s_bin + os) * ws, std::min((v_bin + ov) * wv, 255.0)};
}

int ColorTable::hBin(double h) const {
  double wrapped = std::fmod(h, 360.0);
  if (wrapped < 0) wrapped += 360.0;
  return std::min(static_cast<int>(wrapped * params_.h_bins / 360.0), params_.h_bins - 1);
}

int ColorTable::sBin(double s) const {
  return std::min(static_cast<int>(std::clamp(s, 0.0, 1.0) * params_.s_bins), params_.s_bins - 1);
}

int ColorTable::vBin(double v) const {
  return std::min(static_cast<int>(std::clamp(v, 0.0, 255.0) * params_.v_bins / 256.0), params_.v_bins - 1);
}

ColorTable ColorTable::build(const ClassPixels& samples, const ColorTableParams& params) {
  ClassSamplePixels as_taken;
  for (const auto& [color, pixels] : samples) {
    auto& out = as_taken[color];
    out.reserve(pixels.size());
    for (const cv::Vec3b& p : pixels) out.push_back({p, std::max({p[0], p[1], p[2]})});
  }
  return buildFromSamplePixels(as_taken, params);
}

namespace {

// The claim bits of the robot marker classes of colour, not grey (ColorTableParams::
// lines_yield_to_markers): a pattern whose white quadrants are sampled as a marker class
// (the real 2008 frame's) keeps its lines.
std::uint16_t chromaticMarkerBits(const ColorTableStatistics& stats) {
  std::uint16_t bits = 0;
  for (int c = 0; c < kNumColorClasses; ++c) {
    if (isRobotMarkerColor(static_cast<ColorClass>(c)) && stats.classes[c].valid > 0 &&
        stats.classes[c].mean_s >= kGreySaturation)
      bits |= static_cast<std::uint16_t>(1u << c);
  }
  return bits;
}

// A tenth: on the spent held-out seeds 9061-9063 the markers confused so were yellow tags
// read as the ball's orange, 12-67 % of their colours; no other marker of 8 pixels or
// more reached 7 % (green dots a fifth darker read as carpet, which does not count;
// counted before the condition on the other class's own samples, which only lowers it).
constexpr double kConfusedShare = 0.1;

// The colours a sample pixel stands for in the checks of confusedMarkers: itself, and for
// a robot marker class each of its brightness variants (ColorTableParams::brightness_spread),
// as the table's cells (ColorTable::cellIndex).
template <typename Visit>
void forEachSampleCell(const ColorTable& table, ColorClass color, const SamplePixel& p,
                       const std::vector<double>& factors, Visit visit) {
  const Hsv hsv = bgrToHsv(p.bgr[0], p.bgr[1], p.bgr[2]);
  const int h = table.hBin(hsv.h), s = table.sBin(hsv.s);
  visit(table.cellIndex(h, s, table.vBin(p.v)));
  if (!isRobotMarkerColor(color)) return;
  for (const double f : factors) {
    if (p.v * f <= 255) visit(table.cellIndex(h, s, table.vBin(p.v * f)));
  }
}

// What confusedMarkers found: the markers, and per robot marker class (index: ColorClass)
// the classes its confused markers read as (bit c: class c).
struct Confusions {
  std::set<std::uint32_t> markers;
  std::array<std::uint16_t, kNumColorClasses> read_as{};
};

// The sampled markers of robot marker classes (SamplePixel::marker) with at least
// kMinHueSamples pixels that show their hue, of whose colours (forEachSampleCell) `table`
// reads at least kConfusedShare as another robot marker colour or the ball's orange in a
// cell where none of that class's own samples' colours lies: the same print a little
// darker or brighter would be another marker or a ball only because that class's Gaussian
// reaches so far. Where its samples lie too (two classes sampled on the same colours) the
// table cannot tell them apart, and another build would not either.
Confusions confusedMarkers(const ColorTable& table, const ClassSamplePixels& samples) {
  const std::vector<double> factors = spreadFactors(table.params().brightness_spread);
  std::vector<std::uint16_t> sampled(table.cells().size(), 0);  // bit c: class c's sample colours
  for (const auto& [color, pixels] : samples) {
    const auto bit = static_cast<std::uint16_t>(1u << static_cast<unsigned>(color));
    for (const SamplePixel& p : pixels)
      forEachSampleCell(table, color, p, factors, [&](std::size_t i) { sampled[i] |= bit; });
  }
  Confusions confused;
  for (const auto& [color, pixels] : samples) {
    if (!isRobotMarkerColor(color)) continue;
    struct Count {
      std::size_t pixels = 0, colours = 0, confused = 0;
      std::uint16_t read_as = 0;
    };
    std::map<std::uint32_t, Count> counts;
    for (const SamplePixel& p : pixels) {
      if (p.marker == 0 || !showsItsHue(p)) continue;
      Count& n = counts[p.marker];
      ++n.pixels;
      forEachSampleCell(table, color, p, factors, [&](std::size_t i) {
        const ColorClass c = table.cells()[i];
        const auto bit = static_cast<std::uint16_t>(1u << static_cast<unsigned>(c));
        ++n.colours;
        if (c != color && (isRobotMarkerColor(c) || c == ColorClass::Orange) && !(sampled[i] & bit)) {
          ++n.confused;
          n.read_as |= bit;
        }
      });
    }
    for (const auto& [marker, n] : counts) {
      if (n.pixels < kMinHueSamples || n.confused < kConfusedShare * n.colours) continue;
      confused.markers.insert(marker);
      confused.read_as[static_cast<std::size_t>(color)] |= n.read_as;
    }
  }
  return confused;
}

}  // namespace

// Built once; if the table confuses a sampled marker with another colour
// (confusedMarkers), built again with that marker as another print of its colour
// (ColorTableParams::other_prints). On held-out seed 9063 one yellow tag read hue 36-46°
// where the frame's two others read 54°: most of its pixels were valid, so it was no print
// of its own, and the class's Gaussian, centred between them, lost the cells around it to
// the ball's orange: in the frames after, its robot had no team marker for 2 s, and parts
// of the tag became a ball. The second build settles only the confusions it was built
// for: a cell goes from a colour a marker was read as to the marker's colour, every other
// cell keeps the first build's class. A print's Gaussian of its own also took cells from
// a third class: on the real 2008 frame salmon pink tags read as the ball's orange, and
// their prints took white cells from the quadrants sampled as purple (a robot lost).
ColorTable ColorTable::buildFromSamplePixels(const ClassSamplePixels& samples, const ColorTableParams& params,
                                             const std::vector<SamplePixel>& background,
                                             double brightest_light) {
  const ColorTable first = buildWithPrints(samples, params, background, brightest_light, {});
  if (!params.other_prints) return first;
  const Confusions confused = confusedMarkers(first, samples);
  if (confused.markers.empty()) return first;
  const ColorTable second = buildWithPrints(samples, params, background, brightest_light, confused.markers);
  std::vector<std::pair<std::size_t, ColorClass>> kept;  // the first build's class, where it stays
  for (std::size_t i = 0; i < first.cells_.size(); ++i) {
    const ColorClass was = first.cells_[i], is = second.cells_[i];
    if (was != is && !(confused.read_as[static_cast<std::size_t>(is)] & (1u << static_cast<unsigned>(was))))
      kept.emplace_back(i, was);
  }
  return second.withCells(kept);
}

ColorTable ColorTable::buildWithPrints(const ClassSamplePixels& samples, const ColorTableParams& params,
                                       const std::vector<SamplePixel>& background, double brightest_light,
                                       const std::set<std::uint32_t>& confused) {
  params.validate();
  ColorTable table;
  table.params_ = params;
  const int s_bins = params.s_bins, v_bins = params.v_bins;
  const std::size_t hs_cells = static_cast<std::size_t>(params.h_bins) * s_bins;
  const std::size_t n_cells = hs_cells * v_bins;

  // Bit c of claims[cell] is set when class c's body contains the cell.
  static_assert(kNumColorClasses <= 16, "claims are a 16-bit mask");
  std::vector<std::uint16_t> claims(n_cells, 0);
  // Bit c of clipped_claims[cell]: class c claims it with a colour clipped twice (a sample
  // or the path of ColorTableParams::clipped_twice_path), which its Gaussian does not hold.
  std::vector<std::uint16_t> clipped_claims(n_cells, 0);
  std::vector<int> v_min(hs_cells), v_max(hs_cells);
  // Per HS cell, the lowest and highest V of the colours (none: v_max < v_min).
  auto vRanges = [&](const std::vector<const std::vector<Hsv>*>& colours, std::vector<int>& lo,
                     std::vector<int>& hi) {
    std::fill(lo.begin(), lo.end(), INT_MAX);
    std::fill(hi.begin(), hi.end(), INT_MIN);
    for (const std::vector<Hsv>* list : colours) {
      for (const Hsv& p : *list) {
        const std::size_t hs = static_cast<std::size_t>(table.hBin(p.h)) * s_bins + table.sBin(p.s);
        lo[hs] = std::min(lo[hs], static_cast<int>(p.v));
        hi[hs] = std::max(hi[hs], static_cast<int>(p.v));
      }
    }
  };
  // The cells of those ranges, widened by v_margin, get `bit`.
  auto claimVRanges = [&](const std::vector<int>& lo, const std::vector<int>& hi, std::uint16_t bit,
                          std::vector<std::uint16_t>& out) {
    for (std::size_t hs = 0; hs < hs_cells; ++hs) {
      if (hi[hs] < lo[hs]) continue;
      for (int vb = table.vBin(lo[hs] - params.v_margin); vb <= table.vBin(hi[hs] + params.v_margin); ++vb)
        out[hs * v_bins + vb] |= bit;
    }
  };
  const bool generalize = params.generalize_sigmas > 0;
  std::array<ClassModel, kNumColorClasses> lab_models;
  const std::vector<Lab> probes = generalize ? cellProbeColors(params) : std::vector<Lab>();
  // Cells the background fills: generalisation leaves them alone.
  std::vector<bool> background_cell;
  if (generalize && params.background_share > 0 && !background.empty()) {
    std::vector<std::uint32_t> counts(n_cells, 0);
    for (const SamplePixel& p : background) {
      const Hsv hsv = bgrToHsv(p.bgr[0], p.bgr[1], p.bgr[2]);
      ++counts[(static_cast<std::size_t>(table.hBin(hsv.h)) * s_bins + table.sBin(hsv.s)) * v_bins +
               table.vBin(p.v)];
    }
    const double limit = params.background_share * static_cast<double>(background.size());
    background_cell.resize(n_cells);
    for (std::size_t i = 0; i < n_cells; ++i) background_cell[i] = counts[i] > limit;
  }

  // What the ball's samples are mixed with (ColorTableParams::ball_carpet_mix, _unmix), if anything.
  std::optional<cv::Vec3d> carpet_colour;
  const auto carpet = samples.find(ColorClass::Carpet);
  if (generalize && (params.ball_carpet_mix > 0 || params.ball_carpet_unmix > 0) && carpet != samples.end() &&
      !carpet->second.empty())
    carpet_colour = meanNormalisedColour(carpet->second);

  for (const auto& [color, pixels] : samples) {
    if (color == ColorClass::None || color >= ColorClass::Count) {
      throw std::invalid_argument("colour table: samples for '" + std::string(colorClassName(color)) +
                                  "', which is not a colour class");
    }
    if (pixels.empty()) continue;
    ClassStatistics& st = table.stats_.classes[static_cast<std::size_t>(color)];
    st.samples = static_cast<std::uint32_t>(pixels.size());
    st.thresholds = params.thresholds(color);

    std::vector<Hsv> hsv;
    std::vector<Lab> lab;
    hsv.reserve(pixels.size());
    lab.reserve(pixels.size());
    for (const SamplePixel& sample : pixels) {
      hsv.push_back(bgrToHsv(sample.bgr[0], sample.bgr[1], sample.bgr[2]));
      const cv::Vec3b p = normalisedColour(sample);
      hsv.back().v = sample.v;
      lab.push_back(bgrToLab(p[0], p[1], p[2]));
      st.mean_lab.l += lab.back().l;
      st.mean_lab.a += lab.back().a;
      st.mean_lab.b += lab.back().b;
    }
    const double n = static_cast<double>(pixels.size());
    st.mean_lab = {st.mean_lab.l / n, st.mean_lab.a / n, st.mean_lab.b / n};
    st.mean_h = circularMeanDegrees(hsv);

    std::vector<Hsv> body_only;  // samples that claim their own cells but do not shape the Gaussian
    const SampleCentre centre = markerCentre(color, pixels, lab, hsv, st, body_only);
    const bool marker = isRobotMarkerColor(color);
    PrintColours print = printColours(pixels, hsv, lab, centre.valid, marker, params, brightest_light);
    body_only.insert(body_only.end(), print.body_only.begin(), print.body_only.end());
    std::vector<Hsv>& valid = print.hsv;
    // The ball's samples mixed with the carpet and unmixed from it, level by level.
    std::vector<std::vector<Lab>> mixture_levels;
    if (color == ColorClass::Orange && carpet_colour) {
      for (const double mix : carpetMixtureLevels(params)) {
        std::vector<Hsv> level_hsv;
        std::vector<Lab> level_lab;
        for (std::size_t i = 0; i < pixels.size(); ++i) {
          if (centre.valid[i]) appendCarpetMixVariant(pixels[i], *carpet_colour, mix, level_hsv, level_lab);
        }
        if (level_lab.empty()) continue;
        valid.insert(valid.end(), level_hsv.begin(), level_hsv.end());  // the body, too
        mixture_levels.push_back(std::move(level_lab));
      }
    }
    fitGaussian(valid, params, st);
    // Other prints of the colour: their own cells and Gaussians, not the class's statistics.
    std::vector<std::vector<bool>> other_masks;
    if (params.other_prints && marker)
      other_masks = otherPrints(pixels, lab, hsv, st.thresholds, centre.valid, confused);
    std::vector<PrintColours> others;
    std::vector<bool> valid_in_any = centre.valid;  // a pixel valid in two prints counts once
    for (const std::vector<bool>& mask : other_masks) {
      for (std::size_t i = 0; i < mask.size(); ++i) valid_in_any[i] = valid_in_any[i] || mask[i];
      others.push_back(printColours(pixels, hsv, lab, mask, marker, params, brightest_light));
    }
    st.valid = static_cast<std::uint32_t>(std::count(valid_in_any.begin(), valid_in_any.end(), true));

    // The body: per HS cell, the V bins between its lowest and highest valid pixel.
    std::vector<const std::vector<Hsv>*> bodies = {&valid, &body_only};
    std::vector<const std::vector<Hsv>*> clipped = {&body_only};
    for (const PrintColours& other : others) {
      bodies.push_back(&other.hsv);
      bodies.push_back(&other.body_only);
      clipped.push_back(&other.body_only);
    }
    const auto bit = static_cast<std::uint16_t>(1u << static_cast<unsigned>(color));
    vRanges(bodies, v_min, v_max);
    if (params.hs_closing > 0 && !valid.empty()) closeInHs(params, st, v_min, v_max);
    claimVRanges(v_min, v_max, bit, claims);
    if (params.clipped_cells_own) {
      vRanges(clipped, v_min, v_max);
      claimVRanges(v_min, v_max, bit, clipped_claims);
    }
    if (generalize && !valid.empty()) {
      ClassModel& model = lab_models[static_cast<std::size_t>(color)];
      auto least = [&](const std::vector<bool>& mask) -> Eigen::Matrix3d {
        return params.print_spread > 0 && marker
                   ? printVariantCovariance(pixels, hsv, lab, mask, params.print_spread)
                   : Eigen::Matrix3d::Zero();
      };
      model.parts.push_back(fitLabGaussian(print.lab, params, least(centre.valid)));
      for (const std::vector<Lab>& level : mixture_levels) {
        LabGaussian moved = model.parts.front();
        moved.mean = meanLab(level);
        model.parts.push_back(moved);
      }
      for (std::size_t k = 0; k < others.size(); ++k)
        model.parts.push_back(fitLabGaussian(others[k].lab, params, least(other_masks[k])));
      const double bound = params.generalize_sigmas * params.generalize_sigmas;
      for (std::size_t i = 0; i < n_cells; ++i) {
        if ((claims[i] & bit) || (!background_cell.empty() && background_cell[i])) continue;
        for (int k = 0; k < kCellProbes; ++k) {
          if (model.mahalanobis2(probes[i * kCellProbes + k]) <= bound) {
            claims[i] |= bit;
            break;
          }
        }
      }
    }
    for (std::size_t i = 0; i < n_cells; ++i) st.cells_claimed += (claims[i] & bit) != 0;
  }

  if (generalize && params.fallback_sigmas > 0)
    claimHolesByNearestClass(params, lab_models, probes, background_cell, claims);

  table.cells_.assign(n_cells, ColorClass::None);
  const std::uint16_t chromatic_markers = chromaticMarkerBits(table.stats_);
  const double wh = 360.0 / params.h_bins, ws = 1.0 / s_bins, wv = 256.0 / v_bins;
  for (std::size_t i = 0; i < n_cells; ++i) {
    std::uint16_t mask = claims[i];
    if (mask == 0) continue;
    // A colour clipped twice has no Gaussian to compete with: the classes that saw it have it.
    if (clipped_claims[i] != 0) mask = clipped_claims[i];
    int winner = 0;
    if (std::bitset<16>(mask).count() == 1) {
      while (!(mask & (1u << winner))) ++winner;
    } else {
      ++table.stats_.overlap_cells;
      const std::size_t hs = i / v_bins;
      const double h = (static_cast<double>(hs / s_bins) + 0.5) * wh;
      const double s = (static_cast<double>(hs % s_bins) + 0.5) * ws;
      const double v = (static_cast<double>(i % v_bins) + 0.5) * wv;
      double best = -HUGE_VAL;
      const bool lines_give_way = params.lines_yield_to_markers && (mask & chromatic_markers) != 0;
      for (int c = 0; c < kNumColorClasses; ++c) {
        if (!(mask & (1u << c))) continue;
        if (lines_give_way && c == static_cast<int>(ColorClass::Line)) continue;
        // With generalisation the classes' L*a*b* Gaussians decide, as they claimed.
        const double ll = generalize ? lab_models[c].logLikelihood(probes[i * kCellProbes])
                                     : logLikelihood(table.stats_.classes[c], h, s, v);
        if (ll > best) {  // ties go to the lower class value: deterministic
          best = ll;
          winner = c;
        }
      }
    }
    table.cells_[i] = static_cast<ColorClass>(winner);
    ++table.stats_.classes[winner].cells_assigned;
  }
  return table;
}

ColorTable ColorTable::withIlluminationLevels(cv::Mat levels) const {
  if (!levels.empty() &&
      (levels.type() != CV_32FC1 || levels.dims != 2 || !cv::checkRange(levels, true, nullptr, 1e-3, 1e6))) {
    throw std::invalid_argument(
        "colour table: the illumination levels must be a CV_32FC1 of finite positive levels");
  }
  ColorTable table = *this;
  table.illumination_levels_ = levels.empty() ? cv::Mat() : levels.clone();
  return table;
}

ColorTable ColorTable::withClassesFrom(const ColorTable& other,
                                       const std::vector<ColorClass>& classes) const {
  if (other.params_.h_bins != params_.h_bins || other.params_.s_bins != params_.s_bins ||
      other.params_.v_bins != params_.v_bins) {
    throw std::invalid_argument("colour table: cannot take cells from a table of another quantisation");
  }
  std::array<bool, kNumColorClasses> take{};
  for (const ColorClass c : classes) {
    if (c != ColorClass::None) take[static_cast<int>(c)] = true;
  }
  ColorTable table = *this;
  for (int c = 0; c < kNumColorClasses; ++c) {
    if (take[c]) table.stats_.classes[c] = other.stats_.classes[c];
    table.stats_.classes[c].cells_assigned = 0;
  }
  for (std::size_t i = 0; i < table.cells_.size(); ++i) {
    const ColorClass theirs = other.cells_[i];
    if (table.cells_[i] == ColorClass::None && take[static_cast<int>(theirs)]) table.cells_[i] = theirs;
    ++table.stats_.classes[static_cast<int>(table.cells_[i])].cells_assigned;
  }
  return table;
}

ColorTable ColorTable::withCells(const std::vector<std::pair<std::size_t, ColorClass>>& cells) const {
  ColorTable table = *this;
  for (const auto& [index, c] : cells) table.cells_.at(index) = c;
  for (auto& s : table.stats_.classes) s.cells_assigned = 0;
  for (const ColorClass c : table.cells_) ++table.stats_.classes[static_cast<int>(c)].cells_assigned;
  return table;
}

ColorTable ColorTable::withIlluminationReference(cv::Mat reference) const {
  if (!reference.empty() &&
      (reference.type() != CV_32FC1 || reference.dims != 2 || !cv::checkRange(reference))) {
    throw std::invalid_argument(
        "colour table: the illumination reference must be a CV_32FC1 of finite block means");
  }
  ColorTable table = *this;
  table.illumination_reference_ = reference.empty() ? cv::Mat() : reference.clone();
  return table;
}

// Layout (little-endian):
//   magic[8] | u32 version | u64 file size | u32 class count | u32 h_bins, s_bins, v_bins |
//   f64 threshold_lab, threshold_h | u32 v_margin (since version 3) |
//   u32 override count, {u8 class, f64 lab, f64 h}... |
//   u32 overlap cells | per class: u32 samples, valid, cells claimed, cells assigned,
//   f64 mean L a b, mean h, threshold lab, threshold h, mean h valid, var h, mean s,
//   var s, mean v, var v | u64 cell count, u8 cells... | u32 illumination reference rows,
//   cols, f32 block means row by row (0 x 0: none) | illumination levels, the same way
//   (since version 3) | u32 CRC-32 of all bytes before it
void ColorTable::save(const std::string& path) const {
  ByteWriter w;
  w.bytes(kMagic, sizeof kMagic);
  w.u32(kFormatVersion);
  w.u64(0);  // file size, patched below
  w.u32(kNumColorClasses);
  w.u32(static_cast<std::uint32_t>(params_.h_bins));
  w.u32(static_cast<std::uint32_t>(params_.s_bins));
  w.u32(static_cast<std::uint32_t>(params_.v_bins));
  w.f64(params_.threshold_lab);
  w.f64(params_.threshold_h);
  w.u32(static_cast<std::uint32_t>(params_.v_margin));
  w.u32(static_cast<std::uint32_t>(params_.overrides.size()));
  for (const auto& [c, t] : params_.overrides) {
    w.u8(static_cast<std::uint8_t>(c));
    w.f64(t.lab);
    w.f64(t.h);
  }
  w.u32(stats_.overlap_cells);
  for (const ClassStatistics& st : stats_.classes) writeClassStatistics(w, st);
  w.u64(cells_.size());
  w.bytes(cells_.data(), cells_.size());
  writeBlockMap(w, illumination_reference_);
  writeBlockMap(w, illumination_levels_);
  w.patchU64(kSizeOffset, w.buffer().size() + kChecksumBytes);
  w.u32(crc32(w.buffer().data(), w.buffer().size()));

  try {
    writeFileAtomically(path, w.buffer().data(), w.buffer().size());  // a loading nodelet sees it whole
  } catch (const std::runtime_error&) {
    throw std::runtime_error("colour table '" + path + "': cannot write the file");
  }
}

ColorTable ColorTable::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error("colour table '" + path + "': cannot open the file (missing or unreadable)");
  const std::vector<std::uint8_t> data((std::istreambuf_iterator<char>(in)),
                                       std::istreambuf_iterator<char>());
  ByteReader header(data, 0, data.size(), path);

  // Magic, version and size first: they are where every version puts them, and a file of
  // another version must be named as such, not as corrupt.
  if (data.empty()) header.fail("truncated file (empty)");
  const std::size_t magic_bytes = std::min(data.size(), sizeof kMagic);
  if (std::memcmp(data.data(), kMagic, magic_bytes) != 0)
    header.fail("not a colour table file (wrong magic)");
  if (data.size() < kFixedHeader) header.fail("truncated file (" + std::to_string(data.size()) + " bytes)");
  header.take(sizeof kMagic);
  const std::uint32_t version = header.u32();
  if (version != kFormatVersion && version != 2) {
    header.fail("unsupported format version " + std::to_string(version) + " (this build reads version " +
                std::to_string(kFormatVersion) + ")");
  }
  const std::uint64_t declared = header.u64();
  if (data.size() < declared) {
    header.fail("truncated file (" + std::to_string(data.size()) + " of " + std::to_string(declared) +
                " bytes)");
  }
  if (data.size() > declared || declared < kFixedHeader + kChecksumBytes) {
    header.fail("inconsistent sizes (file has " + std::to_string(data.size()) + " bytes, header declares " +
                std::to_string(declared) + ")");
  }
  const std::size_t body_end = data.size() - kChecksumBytes;
  ByteReader checksum(data, body_end, data.size(), path);
  const std::uint32_t stored = checksum.u32();
  if (stored != crc32(data.data(), body_end)) header.fail("checksum mismatch (file corrupted)");

  ByteReader r(data, kFixedHeader, body_end, path);
  if (r.u32() != static_cast<std::uint32_t>(kNumColorClasses)) {
    r.fail("inconsistent sizes (class count differs from this build's " + std::to_string(kNumColorClasses) +
           ")");
  }
  ColorTable table;
  ColorTableParams& p = table.params_;
  p.h_bins = static_cast<int>(r.u32());
  p.s_bins = static_cast<int>(r.u32());
  p.v_bins = static_cast<int>(r.u32());
  p.threshold_lab = r.f64();
  p.threshold_h = r.f64();
  p.v_margin = version >= 3 ? static_cast<int>(r.u32()) : 0;
  p.overrides.clear();
  const std::uint32_t n_overrides = r.u32();
  for (std::uint32_t i = 0; i < n_overrides; ++i) {
    const auto c = static_cast<ColorClass>(r.u8());
    ClassThresholds t;
    t.lab = r.f64();
    t.h = r.f64();
    p.overrides[c] = t;
  }
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    r.fail(std::string("inconsistent content: ") + e.what());
  }
  table.stats_.overlap_cells = r.u32();
  for (ClassStatistics& st : table.stats_.classes) st = readClassStatistics(r);
  const std::uint64_t n_cells = r.u64();
  const std::uint64_t expected = static_cast<std::uint64_t>(p.h_bins) * p.s_bins * p.v_bins;
  if (n_cells != expected) {
    r.fail("inconsistent sizes (" + std::to_string(n_cells) + " cells for " + std::to_string(p.h_bins) +
           " x " + std::to_string(p.s_bins) + " x " + std::to_string(p.v_bins) + " bins)");
  }
  const std::uint8_t* cells = r.take(n_cells);
  table.cells_.resize(n_cells);
  for (std::size_t i = 0; i < n_cells; ++i) {
    if (cells[i] >= kNumColorClasses)
      r.fail("inconsistent content (cell " + std::to_string(i) + " has no class)");
    table.cells_[i] = static_cast<ColorClass>(cells[i]);
  }
  table.illumination_reference_ = readBlockMap(r, body_end, "illumination reference");
  if (version >= 3) {
    table.illumination_levels_ = readBlockMap(r, body_end, "illumination levels");
    if (!table.illumination_levels_.empty() &&
        !cv::checkRange(table.illumination_levels_, true, nullptr, 1e-3, 1e6)) {
      r.fail("inconsistent content (illumination levels are not positive)");
    }
  }
  if (r.position() != body_end) r.fail("inconsistent sizes (unexpected bytes after the cells)");
  return table;
}

}  // namespace soccer_vision
