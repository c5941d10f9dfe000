#include "soccer_vision/simulation/field_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/simulation/ball_light.h"
#include "soccer_vision/simulation/camera_response.h"
#include "soccer_vision/simulation/carpet_texture.h"
#include "soccer_vision/simulation/distractors.h"
#include "soccer_vision/simulation/lamps.h"

namespace soccer_vision {

namespace {

constexpr double kBallShininess = 20;   // Blinn-Phong exponent of its highlights (a lobe ~15 deg wide)
constexpr int kNoiseMargin = 32;        // px: the noise plane is shifted per frame
constexpr double kBoundsMargin = 0.01;  // m around objects when bounding them
constexpr int kBoundsPoints = 24;       // samples of a circle when bounding it
constexpr float kPenumbra = 0.02f;      // m: width of a lamp shadow's soft edge

const cv::Vec3f kRobotSide = albedoFromRgb(12, 12, 12);  // darker than the top: lit from above

// Fraction of a pixel inside a shape, from the signed distance of the pixel centre
// (negative inside) and the pixel's footprint: exact for a straight edge.
inline float coverage(float sdf, float footprint) { return std::clamp(0.5f - sdf / footprint, 0.f, 1.f); }

// Signed distance to an axis-aligned box of half extents (hx, hy) centred at the origin.
inline float boxSdf(float x, float y, float hx, float hy) {
  const float qx = std::abs(x) - hx, qy = std::abs(y) - hy;
  const float outside = std::hypot(std::max(qx, 0.f), std::max(qy, 0.f));
  return outside + std::min(std::max(qx, qy), 0.f);
}

inline float markerSdf(const MarkerShape& m, float x, float y) {
  const float dx = x - static_cast<float>(m.x), dy = y - static_cast<float>(m.y);
  if (m.kind == MarkerShape::Kind::Disc) return std::hypot(dx, dy) - static_cast<float>(m.radius);
  return boxSdf(dx, dy, static_cast<float>(m.size_x / 2), static_cast<float>(m.size_y / 2));
}

double segmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

std::uint64_t frameSeed(std::uint64_t seed, std::int64_t frame_index) {
  return seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(frame_index) * 0xBF58476D1CE4E5B9ULL + 7;
}

// A robot as seen this frame: pose and its markers with their albedo.
struct RobotLook {
  float x, y, cos_t, sin_t;
  double height;  // m, its team's marker plane (PatternSet::height)
  std::vector<ColoredMarker> markers;
  std::vector<cv::Vec3f> albedo;
};

// One object of one (sub-)frame, in the painter's order of drawing.
struct Drawable {
  bool is_robot;
  std::size_t index;      // into SceneState::robots or ::balls
  cv::Rect box;           // image pixels it may touch
  double nadir_distance;  // horizontal distance from the camera: far ones are drawn first
};

}  // namespace

double shownTimeAfterStamp(const SensorConfig& sensor) {
  return sensor.blur_samples > 1 ? sensor.exposure / 2 : 0.0;
}

struct FieldRenderer::Impl {
  CameraModel camera;
  FieldGeometry field;
  PatternSet patterns;
  ScenarioConfig scenario;
  IlluminationModel illumination;
  LampSet lamps;
  CarpetTexture carpet_texture;
  CameraResponse response;
  std::vector<Distractor> distractors;
  int width, height;
  Eigen::Vector3d centre;  // camera centre in `field`
  Eigen::Isometry3d camera_T_field;
  double fold_radius = HUGE_VAL;  // normalised radius where the distortion folds back
  std::string encoding = "bgr8";
  std::array<std::array<int, 2>, 2> bayer_channel{};  // [row & 1][col & 1] -> B/G/R index
  bool bayer = false;                                 // the output is the raw mosaic
  bool camera_demosaic = false;                       // mosaic, then the camera's own demosaic: BGR output

  cv::Mat ground;                   // CV_32FC2: where each pixel's ray meets z = 0
  cv::Mat footprint;                // CV_32F: side of the pixel's footprint on z = 0, m
  cv::Mat gain;                     // CV_32F: spatial illumination gain (lamps without drift)
  cv::Mat smooth_gain;              // CV_32F: the IlluminationModel's part of it
  std::vector<cv::Mat> lamp_light;  // CV_32F per lamp: its irradiance at each pixel's ground point
  cv::Mat background_albedo;        // CV_32FC3: floor, carpet (textured), lines, distractors
  cv::Mat lit_background;           // CV_32FC3: background albedo * gain
  cv::Mat background_labels;        // CV_8U: ColorClass
  cv::Mat noise;                    // CV_32FC3, kNoiseMargin larger; empty when noise is off

  Impl(const CameraModel& cam, const FieldGeometry& f, const PatternSet& p, const ScenarioConfig& s)
      : camera(cam),
        field(f),
        patterns(p),
        scenario(s),
        illumination(s.lighting, f, s.seed),
        lamps(s.appearance, f, s.seed),
        carpet_texture(s.appearance, s.seed),
        response(s.appearance, s.sensor, cam.width(), cam.height(), s.seed),
        distractors(distractorLayout(s.appearance.distractors, f, s.seed)),
        width(cam.width()),
        height(cam.height()),
        centre(cam.cameraCentre()),
        camera_T_field(cam.fieldTCamera().inverse()) {
    parseBayer();
    findFoldRadius();
    buildRayMaps();
    buildBackground();
    if (scenario.sensor.noise_sigma > 0) {
      noise.create(height + kNoiseMargin, width + kNoiseMargin, CV_32FC3);
      cv::RNG rng(frameSeed(scenario.seed, -1));
      rng.fill(noise, cv::RNG::NORMAL, 0.0, scenario.sensor.noise_sigma);
    }
  }

  void parseBayer() {
    const std::string& b = scenario.sensor.bayer;
    if (b.empty()) return;
    auto channel = [](char c) { return c == 'b' ? 0 : c == 'g' ? 1 : 2; };
    if (b != "rggb" && b != "bggr" && b != "gbrg" && b != "grbg")
      throw std::invalid_argument("FieldRenderer: unknown Bayer pattern '" + b + "'");
    bayer = true;
    encoding = "bayer_" + b + "8";
    bayer_channel = {{{channel(b[0]), channel(b[1])}, {channel(b[2]), channel(b[3])}}};
    if (scenario.appearance.demosaic) {
      bayer = false;
      camera_demosaic = true;
      encoding = "bgr8";
    }
  }

  // Beyond this radius the radial polynomial is no longer monotonic: projecting such a
  // point folds it back into the image, so bounds treat it as far outside instead.
  void findFoldRadius() {
    const auto& k = camera.intrinsics().dist;
    for (double r = 0.01; r < 10; r += 0.01) {
      const double r2 = r * r;
      if (1 + 3 * k[0] * r2 + 5 * k[1] * r2 * r2 + 7 * k[4] * r2 * r2 * r2 <= 0) {
        fold_radius = 0.95 * r;
        return;
      }
    }
  }

  void buildRayMaps() {
    ground.create(height, width, CV_32FC2);
    for (int v = 0; v < height; ++v) {
      auto* g = ground.ptr<cv::Vec2f>(v);
      for (int u = 0; u < width; ++u) {
        const Eigen::Vector3d ray = camera.pixelRay(Eigen::Vector2d(u, v));
        // A ray that never comes down sees the far floor.
        const double t = ray.z() < -1e-9 ? -centre.z() / ray.z() : 1e4;
        g[u] = cv::Vec2f(static_cast<float>(centre.x() + t * ray.x()),
                         static_cast<float>(centre.y() + t * ray.y()));
      }
    }
    // Footprint side = sqrt of the local area scale of the map (central differences).
    footprint.create(height, width, CV_32F);
    for (int v = 0; v < height; ++v) {
      const int v0 = std::max(v - 1, 0), v1 = std::min(v + 1, height - 1);
      for (int u = 0; u < width; ++u) {
        const int u0 = std::max(u - 1, 0), u1 = std::min(u + 1, width - 1);
        const cv::Vec2f du = (ground.at<cv::Vec2f>(v, u1) - ground.at<cv::Vec2f>(v, u0)) / (u1 - u0);
        const cv::Vec2f dv = (ground.at<cv::Vec2f>(v1, u) - ground.at<cv::Vec2f>(v0, u)) / (v1 - v0);
        const float area = std::abs(du[0] * dv[1] - du[1] * dv[0]);
        footprint.at<float>(v, u) = area > 0 && std::isfinite(area) ? std::sqrt(area) : 1.f;
      }
    }
  }

  void buildBackground() {
    const std::vector<LineSegment> lines = field.lines();
    const std::vector<CircleArc> circles = field.circles();
    const float carpet_hx = static_cast<float>(field.carpetHalfLength());
    const float carpet_hy = static_cast<float>(field.carpetHalfWidth());
    const double half_line = field.line_width / 2;
    const cv::Vec3f floor = classAlbedo(ColorClass::None);
    const cv::Vec3f carpet = classAlbedo(ColorClass::Carpet);
    const cv::Vec3f line = classAlbedo(ColorClass::Line);

    smooth_gain.create(height, width, CV_32F);
    background_albedo.create(height, width, CV_32FC3);
    background_labels.create(height, width, CV_8U);
    for (std::size_t k = 0; k < lamps.size(); ++k) lamp_light.emplace_back(height, width, CV_32F);
    for (int v = 0; v < height; ++v) {
      const auto* g = ground.ptr<cv::Vec2f>(v);
      const float* fp = footprint.ptr<float>(v);
      float* gn = smooth_gain.ptr<float>(v);
      auto* albedo = background_albedo.ptr<cv::Vec3f>(v);
      auto* label = background_labels.ptr<std::uint8_t>(v);
      for (int u = 0; u < width; ++u) {
        const Eigen::Vector2d p(g[u][0], g[u][1]);
        const float on_carpet = coverage(boxSdf(g[u][0], g[u][1], carpet_hx, carpet_hy), fp[u]);
        double line_sdf = HUGE_VAL;
        if (on_carpet > 0) {
          for (const LineSegment& s : lines) line_sdf = std::min(line_sdf, segmentDistance(p, s.a, s.b));
          for (const CircleArc& c : circles) line_sdf = std::min(line_sdf, c.distance(p));
        }
        const float on_line = coverage(static_cast<float>(line_sdf - half_line), fp[u]);
        gn[u] = static_cast<float>(illumination.spatialGain(p.x(), p.y()));
        for (std::size_t k = 0; k < lamps.size(); ++k)
          lamp_light[k].at<float>(v, u) = static_cast<float>(lamps.irradiance(k, p.x(), p.y()));
        const cv::Vec3f textured = on_carpet > 0 && carpet_texture.active()
                                       ? carpet * static_cast<float>(carpet_texture.shade(p.x(), p.y()))
                                       : carpet;
        albedo[u] = floor * (1 - on_carpet) + on_carpet * (textured * (1 - on_line) + line * on_line);
        label[u] = static_cast<std::uint8_t>(on_carpet < 0.5f  ? ColorClass::None
                                             : on_line >= 0.5f ? ColorClass::Line
                                                               : ColorClass::Carpet);
        if (!distractors.empty() && distanceOutsideLines(field, p.x(), p.y()) > 0) {
          for (const Distractor& d : distractors) {
            if (std::hypot(p.x() - d.x, p.y() - d.y) > d.boundingRadius() + fp[u]) continue;
            const float c = coverage(d.sdf(g[u][0], g[u][1]), fp[u]);
            albedo[u] = albedo[u] * (1 - c) + c * d.albedo;
            if (c >= 0.5f) label[u] = static_cast<std::uint8_t>(ColorClass::None);
          }
        }
      }
    }
    gain = lampGain(std::vector<double>(lamps.size(), 1.0));
    lit_background = litBy(gain);
  }

  // The spatial gain with each lamp at its relative intensity.
  cv::Mat lampGain(const std::vector<double>& intensity) const {
    if (lamps.empty()) return smooth_gain;
    cv::Mat sum(height, width, CV_32F, cv::Scalar(0));
    for (std::size_t k = 0; k < lamps.size(); ++k) cv::scaleAdd(lamp_light[k], intensity[k], sum, sum);
    return sum.mul(smooth_gain);
  }

  cv::Mat litBy(const cv::Mat& spatial_gain) const {
    cv::Mat gain3, lit;
    cv::merge(std::vector<cv::Mat>{spatial_gain, spatial_gain, spatial_gain}, gain3);
    cv::multiply(background_albedo, gain3, lit);
    return lit;
  }

  std::vector<double> lampIntensities(double t) const {
    std::vector<double> out;
    for (std::size_t k = 0; k < lamps.size(); ++k) out.push_back(lamps.drift(k, t));
    return out;
  }

  bool castsShadows() const { return !lamps.empty() && scenario.appearance.shadow > 0; }

  // How far beyond its axis a robot's shadows may reach on the carpet.
  double shadowReach(const RobotState& r) const {
    double reach = 0;
    for (std::size_t k = 0; k < lamps.size(); ++k)
      reach = std::max(
          reach, (lamps.shadowTip(k, r.x, r.y, patterns.height(r.team)) - Eigen::Vector2d(r.x, r.y)).norm());
    return reach + 2 * kPenumbra;
  }

  // Field point -> raw pixel for bounding boxes; points past the distortion fold are sent
  // far out in their own direction.
  std::optional<Eigen::Vector2d> projectForBounds(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d pc = camera_T_field * p;
    if (pc.z() <= 1e-6) return std::nullopt;
    const Eigen::Vector2d n = pc.head<2>() / pc.z();
    if (n.norm() < fold_radius) return camera.project(p);
    const CameraIntrinsics& k = camera.intrinsics();
    return Eigen::Vector2d(k.cx + k.fx * n.x() * 1e3, k.cy + k.fy * n.y() * 1e3);
  }

  // Pixel box around circles (x, y, radius) at the given heights; empty when off-image.
  cv::Rect boundCircles(double x, double y, double radius, std::initializer_list<double> heights) const {
    double u0 = HUGE_VAL, v0 = HUGE_VAL, u1 = -HUGE_VAL, v1 = -HUGE_VAL;
    for (double z : heights)
      for (int k = 0; k < kBoundsPoints; ++k) {
        const double a = 2 * M_PI * k / kBoundsPoints;
        // Polygon around the circle: vertices at radius / cos(half step) enclose it.
        const double rr = radius / std::cos(M_PI / kBoundsPoints) + kBoundsMargin;
        const auto px = projectForBounds({x + rr * std::cos(a), y + rr * std::sin(a), z});
        if (!px) return cv::Rect(0, 0, width, height);
        u0 = std::min(u0, px->x());
        u1 = std::max(u1, px->x());
        v0 = std::min(v0, px->y());
        v1 = std::max(v1, px->y());
      }
    const cv::Rect image(0, 0, width, height);
    if (u1 < -2 || v1 < -2 || u0 > width + 2 || v0 > height + 2) return {};
    const int l = static_cast<int>(std::floor(std::max(u0, -1.0))) - 2;
    const int t = static_cast<int>(std::floor(std::max(v0, -1.0))) - 2;
    const int r = static_cast<int>(std::ceil(std::min(u1, width + 1.0))) + 3;
    const int b = static_cast<int>(std::ceil(std::min(v1, height + 1.0))) + 3;
    return cv::Rect(l, t, r - l, b - t) & image;
  }

  std::vector<Drawable> drawables(const SceneState& scene) const {
    std::vector<Drawable> out;
    for (std::size_t i = 0; i < scene.robots.size(); ++i) {
      const RobotState& r = scene.robots[i];
      const double reach = castsShadows() ? shadowReach(r) : 0.0;
      out.push_back({true, i,
                     boundCircles(r.x, r.y, patterns.robot_radius + reach, {0.0, patterns.height(r.team)}),
                     std::hypot(r.x - centre.x(), r.y - centre.y())});
    }
    for (std::size_t i = 0; i < scene.balls.size(); ++i) {
      const BallState& b = scene.balls[i];
      out.push_back({false, i,
                     boundCircles(b.x, b.y, kBallRadius, {b.z - kBallRadius, b.z, b.z + kBallRadius}),
                     std::hypot(b.x - centre.x(), b.y - centre.y())});
    }
    std::stable_sort(out.begin(), out.end(), [](const Drawable& a, const Drawable& b) {
      return a.nadir_distance > b.nadir_distance;
    });
    return out;
  }

  RobotLook look(const RobotState& r) const {
    RobotLook l{static_cast<float>(r.x),
                static_cast<float>(r.y),
                static_cast<float>(std::cos(r.theta)),
                static_cast<float>(std::sin(r.theta)),
                patterns.height(r.team),
                patterns.markers(r.team, r.id),
                {}};
    for (const ColoredMarker& m : l.markers) l.albedo.push_back(classAlbedo(m.color));
    const double spread = scenario.appearance.marker_albedo_spread;
    if (spread > 0) {
      // Each printed marker its own colour, the same in every frame.
      for (std::size_t k = 0; k < l.albedo.size(); ++k) {
        cv::RNG rng(scenario.seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(r.team) * 7919 +
                    static_cast<std::uint64_t>(r.id) * 104729 + k * 1299709 + 5);
        for (int ch = 0; ch < 3; ++ch)
          l.albedo[k][ch] *= static_cast<float>(std::max(0.2, 1 + spread * rng.gaussian(1.0)));
      }
    }
    return l;
  }

  // Everything about a pixel's ray and one robot: silhouette coverage, top-disc coverage,
  // and where the ray crosses the top plane, in the robot frame.
  struct RobotRay {
    float body, top, local_x, local_y, footprint_top;
  };

  RobotRay traceRobot(const RobotLook& l, cv::Vec2f g, float fp) const {
    const float cx = static_cast<float>(centre.x()), cy = static_cast<float>(centre.y());
    // All rays meet at the camera centre, so the z = h plane is z = 0 scaled to the nadir.
    const float s = static_cast<float>((centre.z() - l.height) / centre.z());
    const float radius = static_cast<float>(patterns.robot_radius);
    const float tx = cx + (g[0] - cx) * s, ty = cy + (g[1] - cy) * s;
    // Horizontal trace of the ray from the top plane down to the carpet: it hits the
    // cylinder where that segment comes within the radius of the axis.
    const float sx = g[0] - tx, sy = g[1] - ty;
    const float len2 = sx * sx + sy * sy;
    const float t = len2 > 0 ? std::clamp(((l.x - tx) * sx + (l.y - ty) * sy) / len2, 0.f, 1.f) : 0.f;
    const float axis_distance = std::hypot(tx + t * sx - l.x, ty + t * sy - l.y);
    const float fp_top = fp * s;
    RobotRay ray{};
    ray.body = coverage(axis_distance - radius, fp_top);
    ray.footprint_top = fp_top;
    if (ray.body <= 0) return ray;
    const float dx = tx - l.x, dy = ty - l.y;
    ray.top = std::min(ray.body, coverage(std::hypot(dx, dy) - radius, fp_top));
    ray.local_x = l.cos_t * dx + l.sin_t * dy;
    ray.local_y = -l.sin_t * dx + l.cos_t * dy;
    return ray;
  }

  // Darkens the background in the soft shadows robot `r` casts from every lamp: the share
  // of the light each lamp brings there, times the share of it the robot blocks.
  void shadeShadows(const RobotState& r, const std::vector<double>& intensity, const cv::Rect& area,
                    cv::Mat& patch, cv::Point origin) const {
    const float radius = static_cast<float>(patterns.robot_radius);
    const Eigen::Vector2d base(r.x, r.y);
    std::vector<Eigen::Vector2d> tips;
    for (std::size_t k = 0; k < lamps.size(); ++k)
      tips.push_back(lamps.shadowTip(k, r.x, r.y, patterns.height(r.team)));
    const float strength = static_cast<float>(scenario.appearance.shadow);
    for (int v = area.y; v < area.br().y; ++v) {
      const auto* g = ground.ptr<cv::Vec2f>(v);
      const float* fp = footprint.ptr<float>(v);
      auto* out = patch.ptr<cv::Vec3f>(v - origin.y) - origin.x;
      for (int u = area.x; u < area.br().x; ++u) {
        const Eigen::Vector2d p(g[u][0], g[u][1]);
        double total = 0, blocked = 0;
        for (std::size_t k = 0; k < lamps.size(); ++k) {
          const double light = intensity[k] * lamp_light[k].at<float>(v, u);
          total += light;
          const float sdf = static_cast<float>(segmentDistance(p, base, tips[k])) - radius;
          blocked += light * coverage(sdf, kPenumbra + fp[u]);
        }
        if (blocked > 0) out[u] *= 1 - strength * static_cast<float>(blocked / total);
      }
    }
  }

  void drawRobot(const RobotLook& l, const cv::Mat& spatial_gain, const cv::Rect& area, cv::Mat& patch,
                 cv::Point origin) const {
    const cv::Vec3f top_albedo = classAlbedo(ColorClass::RobotTop);
    for (int v = area.y; v < area.br().y; ++v) {
      const auto* g = ground.ptr<cv::Vec2f>(v);
      const float* fp = footprint.ptr<float>(v);
      const float* gn = spatial_gain.ptr<float>(v);
      auto* out = patch.ptr<cv::Vec3f>(v - origin.y) - origin.x;
      for (int u = area.x; u < area.br().x; ++u) {
        const RobotRay ray = traceRobot(l, g[u], fp[u]);
        if (ray.body <= 0) continue;
        cv::Vec3f top = top_albedo;
        if (ray.top > 0) {
          float painted = 0;
          cv::Vec3f paint(0, 0, 0);
          for (std::size_t k = 0; k < l.markers.size(); ++k) {
            const float c =
                coverage(markerSdf(l.markers[k].shape, ray.local_x, ray.local_y), ray.footprint_top);
            painted += c;
            paint += c * l.albedo[k];
          }
          top = paint + std::max(0.f, 1 - painted) * top_albedo;
        }
        out[u] = out[u] * (1 - ray.body) + gn[u] * ((ray.body - ray.top) * kRobotSide + ray.top * top);
      }
    }
  }

  void labelRobot(const RobotLook& l, const cv::Rect& area, cv::Mat& labels) const {
    for (int v = area.y; v < area.br().y; ++v) {
      const auto* g = ground.ptr<cv::Vec2f>(v);
      const float* fp = footprint.ptr<float>(v);
      auto* out = labels.ptr<std::uint8_t>(v);
      for (int u = area.x; u < area.br().x; ++u) {
        const RobotRay ray = traceRobot(l, g[u], fp[u]);
        if (ray.body < 0.5f) continue;
        ColorClass c = ray.top >= 0.5f ? ColorClass::RobotTop : ColorClass::None;
        if (c == ColorClass::RobotTop)
          for (const ColoredMarker& m : l.markers)
            if (markerSdf(m.shape, ray.local_x, ray.local_y) <= 0) c = m.color;
        out[u] = static_cast<std::uint8_t>(c);
      }
    }
  }

  // Distance of each pixel's ray from the ball centre (double: the difference of two
  // ~16 m^2 terms must resolve 0.1 mm), the distance along the ray (carpet = 1), and the
  // ray (camera centre to the carpet).
  template <typename Fn>
  void traceBall(const BallState& b, const cv::Rect& area, Fn&& fn) const {
    const Eigen::Vector3d w = Eigen::Vector3d(b.x, b.y, b.z) - centre;
    for (int v = area.y; v < area.br().y; ++v) {
      const auto* g = ground.ptr<cv::Vec2f>(v);
      for (int u = area.x; u < area.br().x; ++u) {
        const Eigen::Vector3d d(g[u][0] - centre.x(), g[u][1] - centre.y(), -centre.z());
        const double dd = d.squaredNorm(), wd = w.dot(d);
        const double distance = std::sqrt(std::max(0.0, w.squaredNorm() - wd * wd / dd));
        fn(u, v, static_cast<float>(distance), static_cast<float>(wd / dd), d);
      }
    }
  }

  void drawBall(const BallState& b, const cv::Mat& spatial_gain, const std::vector<double>& intensity,
                const cv::Rect& area, cv::Mat& patch, cv::Point origin) const {
    const cv::Vec3f orange = classAlbedo(ColorClass::Orange);
    const cv::Vec3f white = albedoFromRgb(255, 255, 255);  // a highlight has the light's colour
    const float radius = static_cast<float>(kBallRadius);
    const double lit = scenario.appearance.ball_shading, gloss = scenario.appearance.ball_gloss;
    const Eigen::Vector3d ball(b.x, b.y, b.z);
    const BallLight light(lamps, intensity, ball);
    traceBall(b, area, [&](int u, int v, float distance, float along, const Eigen::Vector3d& ray) {
      const float c = coverage(distance - radius, footprint.at<float>(v, u) * along);
      if (c <= 0) return;
      // Soft shading symmetric about the view ray: it keeps the centroid on the centre.
      const float q = std::min(1.f, distance / radius);
      float shade = 0.75f + 0.25f * std::sqrt(1 - q * q);
      float highlight = 0;
      if (lit > 0 || gloss > 0) {
        // Where the ray meets the sphere (at its rim for the edge's partly covered pixels).
        const double n = ray.norm(), half_chord = kBallRadius * std::sqrt(1.0 - double(q) * q);
        const Eigen::Vector3d normal = (centre + ray * ((along * n - half_chord) / n) - ball).normalized();
        shade = static_cast<float>((1 - lit) * shade + lit * light.diffuse(normal));
        highlight = static_cast<float>(gloss * light.specular(normal, -ray / n, kBallShininess));
      }
      const float g = spatial_gain.at<float>(v, u);
      cv::Vec3f& out = patch.at<cv::Vec3f>(v - origin.y, u - origin.x);
      out = out * (1 - c) + (c * shade * g) * orange + (c * highlight * g) * white;
    });
  }

  void labelBall(const BallState& b, const cv::Rect& area, cv::Mat& labels) const {
    traceBall(b, area, [&](int u, int v, float distance, float, const Eigen::Vector3d&) {
      if (distance <= kBallRadius)
        labels.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(ColorClass::Orange);
    });
  }

  // Objects of one (sub-)frame painted over the lit background inside `region`.
  void paintObjects(const SceneState& scene, const std::vector<Drawable>& items, const cv::Rect& region,
                    const cv::Mat& gain_now, const std::vector<double>& intensity, cv::Mat& patch) const {
    if (castsShadows()) {
      for (const Drawable& d : items) {
        const cv::Rect area = d.box & region;
        if (d.is_robot && !area.empty())
          shadeShadows(scene.robots[d.index], intensity, area, patch, region.tl());
      }
    }
    for (const Drawable& d : items) {
      const cv::Rect area = d.box & region;
      if (area.empty()) continue;
      if (d.is_robot)
        drawRobot(look(scene.robots[d.index]), gain_now, area, patch, region.tl());
      else
        drawBall(scene.balls[d.index], gain_now, intensity, area, patch, region.tl());
    }
  }

  // Lit albedo -> 8-bit: global gain, additive noise, saturation.
  void expose(const cv::Mat& lit, double global_gain, const cv::Mat& noise_view, cv::Mat dst) const {
    if (noise_view.empty())
      lit.convertTo(dst, CV_8U, global_gain);
    else
      cv::addWeighted(lit, global_gain, noise_view, 1.0, 0.0, dst, CV_8U);
  }

  void renderBgr(const SceneState& scene, std::int64_t frame_index, cv::Mat& bgr) const {
    const double global_gain = illumination.globalGain(scene.time, frame_index);
    cv::Mat noise_view;
    if (!noise.empty()) {
      cv::RNG rng(frameSeed(scenario.seed, frame_index));
      const int dx = rng.uniform(0, kNoiseMargin + 1), dy = rng.uniform(0, kNoiseMargin + 1);
      noise_view = noise(cv::Rect(dx, dy, width, height));
    }
    // Lamps drifting on their own change the light's shape, not only its level.
    const bool drifting = !lamps.empty() && scenario.appearance.lamp_drift > 0;
    const std::vector<double> intensity =
        drifting ? lampIntensities(scene.time) : std::vector<double>(lamps.size(), 1.0);
    const cv::Mat gain_now = drifting ? lampGain(intensity) : gain;
    const cv::Mat lit_now = drifting ? litBy(gain_now) : lit_background;
    // With a camera response the frame is composed in linear light first.
    cv::Mat linear;
    if (response.active())
      linear = lit_now.clone();
    else
      expose(lit_now, global_gain, noise_view, bgr);

    // Sub-exposures for motion blur; objects are redrawn only inside the regions they sweep.
    const int samples = std::max(1, scenario.sensor.blur_samples);
    std::vector<SceneState> states;
    std::vector<std::vector<Drawable>> items;
    for (int k = 0; k < samples; ++k) {
      // Evenly over the exposure: their mean is shownTimeAfterStamp().
      states.push_back(samples == 1 ? scene
                                    : extrapolate(scene, scenario.sensor.exposure * (k + 0.5) / samples));
      items.push_back(drawables(states.back()));
    }
    std::vector<cv::Rect> regions;
    for (const auto& list : items)
      for (const Drawable& d : list)
        if (!d.box.empty()) regions.push_back(d.box);
    mergeOverlapping(regions);

    for (const cv::Rect& region : regions) {
      cv::Mat sum(region.size(), CV_32FC3, cv::Scalar::all(0));
      cv::Mat patch;
      for (int k = 0; k < samples; ++k) {
        lit_now(region).copyTo(patch);
        paintObjects(states[k], items[k], region, gain_now, intensity, patch);
        sum += patch;
      }
      if (samples > 1) sum *= 1.0 / samples;
      if (response.active())
        sum.copyTo(linear(region));
      else
        expose(sum, global_gain, noise_view.empty() ? cv::Mat() : noise_view(region), bgr(region));
    }
    if (response.active()) response.apply(linear, global_gain, noise_view, frame_index, bgr);
  }

  // Overlapping boxes become their union, so no pixel is accumulated twice.
  static void mergeOverlapping(std::vector<cv::Rect>& rects) {
    for (bool merged = true; merged;) {
      merged = false;
      for (std::size_t i = 0; i < rects.size() && !merged; ++i)
        for (std::size_t j = i + 1; j < rects.size() && !merged; ++j)
          if (!(rects[i] & rects[j]).empty()) {
            rects[i] |= rects[j];
            rects.erase(rects.begin() + static_cast<std::ptrdiff_t>(j));
            merged = true;
          }
    }
  }

  void mosaic(const cv::Mat& bgr, cv::Mat& raw) const {
    for (int v = 0; v < height; ++v) {
      const auto* in = bgr.ptr<cv::Vec3b>(v);
      auto* out = raw.ptr<std::uint8_t>(v);
      const auto& channel = bayer_channel[v & 1];
      for (int u = 0; u < width; u += 2) out[u] = in[u][channel[0]];
      for (int u = 1; u < width; u += 2) out[u] = in[u][channel[1]];
    }
  }
};

FieldRenderer::FieldRenderer(const CameraModel& camera, const FieldGeometry& field,
                             const PatternSet& patterns, const ScenarioConfig& scenario)
    : impl_(std::make_unique<Impl>(camera, field, patterns, scenario)) {}

FieldRenderer::~FieldRenderer() = default;

void FieldRenderer::render(const SceneState& scene, std::int64_t frame_index, RenderedFrame& out) const {
  const Impl& m = *impl_;
  out.encoding = m.encoding;
  out.image.create(m.height, m.width, m.bayer ? CV_8UC1 : CV_8UC3);
  const int quality = m.scenario.sensor.jpeg_quality;
  if (!m.bayer && !m.camera_demosaic && quality <= 0) {
    m.renderBgr(scene, frame_index, out.image);
    return;
  }
  thread_local cv::Mat bgr;  // scratch of the colour image before JPEG / mosaic
  bgr.create(m.height, m.width, CV_8UC3);
  m.renderBgr(scene, frame_index, bgr);
  if (m.camera_demosaic) {
    // What a colour camera outputs: its sensor's mosaic, interpolated by its own demosaic.
    // OpenCV names Bayer patterns by the second row: an RGGB mosaic is COLOR_BayerBG2BGR.
    thread_local cv::Mat raw;
    raw.create(m.height, m.width, CV_8UC1);
    m.mosaic(bgr, raw);
    const std::string& b = m.scenario.sensor.bayer;
    const int code = b == "rggb"   ? cv::COLOR_BayerBG2BGR
                     : b == "bggr" ? cv::COLOR_BayerRG2BGR
                     : b == "gbrg" ? cv::COLOR_BayerGR2BGR
                                   : cv::COLOR_BayerGB2BGR;
    cv::cvtColor(raw, bgr, code);
  }
  if (quality > 0) {
    thread_local std::vector<std::uint8_t> jpeg;
    cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, std::min(quality, 100)});
    cv::imdecode(jpeg, cv::IMREAD_COLOR, &bgr);
  }
  if (m.bayer)
    m.mosaic(bgr, out.image);
  else
    bgr.copyTo(out.image);
}

cv::Mat FieldRenderer::renderLabels(const SceneState& scene) const {
  const Impl& m = *impl_;
  cv::Mat labels = m.background_labels.clone();
  for (const Drawable& d : m.drawables(scene)) {
    if (d.box.empty()) continue;
    if (d.is_robot)
      m.labelRobot(m.look(scene.robots[d.index]), d.box, labels);
    else
      m.labelBall(scene.balls[d.index], d.box, labels);
  }
  return labels;
}

std::string FieldRenderer::encoding() const { return impl_->encoding; }

const CameraModel& FieldRenderer::camera() const { return impl_->camera; }

bool FieldRenderer::robotVisible(const RobotState& robot) const {
  const Impl& m = *impl_;
  for (const Eigen::Vector3d& p :
       markerOutlinePoints(m.patterns, robot.team, robot.id, robot.x, robot.y, robot.theta)) {
    const auto px = m.projectForBounds(p);
    if (!px || !m.camera.inImage(*px)) return false;
  }
  return true;
}

double FieldRenderer::ballShown(const BallState& ball, const std::vector<RobotState>& robots) const {
  const Impl& m = *impl_;
  const double r = kBallRadius;
  const Eigen::Vector3d c(ball.x, ball.y, ball.z);
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d(r, 0, 0), Eigen::Vector3d(-r, 0, 0), Eigen::Vector3d(0, r, 0),
        Eigen::Vector3d(0, -r, 0), Eigen::Vector3d(0, 0, r)}) {
    const auto px = m.projectForBounds(c + offset);
    if (!px || !m.camera.inImage(*px)) return 0;
  }
  // Seen by the camera: a ball beside a robot on its far side from the nadir lies behind the
  // robot's body (a 150 mm robot 2 m from the nadir covers 75 mm beyond its footprint). The
  // ball's image is sampled on the disc facing the camera.
  const Eigen::Vector3d view = (m.centre - c).normalized();
  const Eigen::Vector3d e1 = view.unitOrthogonal(), e2 = view.cross(e1);
  int samples = 0, seen = 0;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      if (i * i + j * j > 4) continue;
      const Eigen::Vector3d p = c + (e1 * i + e2 * j) * (r / 2);
      ++samples;
      seen += std::none_of(robots.begin(), robots.end(), [&](const RobotState& robot) {
        const double h = m.patterns.height(robot.team);
        if (p.z() >= h) return false;
        // The ray from p towards the camera inside the body's height band: from p up to z = h.
        const Eigen::Vector3d q = p + (m.centre - p) * ((h - p.z()) / (m.centre.z() - p.z()));
        return segmentDistance(Eigen::Vector2d(robot.x, robot.y), p.head<2>(), q.head<2>()) <
               m.patterns.robot_radius;
      });
    }
  }
  return static_cast<double>(seen) / samples;
}

bool FieldRenderer::ballVisible(const BallState& ball, const std::vector<RobotState>& robots) const {
  return ballShown(ball, robots) >= 0.5;
}

SceneState FieldRenderer::withWhollyVisibleBalls(const SceneState& scene) const {
  SceneState shown = scene;
  shown.balls.clear();
  for (const BallState& b : scene.balls) {
    if (ballShown(b, scene.robots) == 1.0) shown.balls.push_back(b);
  }
  return shown;
}

ColorSamples FieldRenderer::paintedSamples(const SceneState& scene, const SampleOptions& options) const {
  const Impl& m = *impl_;
  return calibrationSamples(withWhollyVisibleBalls(scene), m.camera, m.field, m.patterns, options);
}

}  // namespace soccer_vision
