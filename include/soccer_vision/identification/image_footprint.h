// How large a marker or the ball appears at a given place in the image: the outline of
// the shape on its plane (or the ball's silhouette circle) projected through the camera
// model, its pixel area by the shoelace formula. Used to judge whether a region's area
// is plausible for what it is taken to be.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/robot_pattern.h"

namespace soccer_vision {

// Outline (field frame, counter-clockwise) of a pattern shape on a robot at (x, y, theta),
// on the plane z. Discs get `disc_points` vertices, rectangles their 4 corners (each side
// subdivided into `disc_points / 4` for the lens curvature).
std::vector<Eigen::Vector3d> markerOutline(const MarkerShape& shape, double x, double y, double theta,
                                           double z, int disc_points = 16);

// Pixel area of a closed field-frame polygon in the raw image; 0 if a vertex is behind the camera.
double projectedArea(const CameraModel& camera, const std::vector<Eigen::Vector3d>& outline);

// Expected pixel area of a marker of a robot at (x, y, theta), marker plane z.
double expectedMarkerArea(const CameraModel& camera, const MarkerShape& shape, double x, double y,
                          double theta, double z);

// Expected pixel area of a sphere (the ball) of `radius` centred at `centre`: its
// silhouette is the circle of tangent points seen from the camera centre.
double expectedBallArea(const CameraModel& camera, const Eigen::Vector3d& centre, double radius,
                        int points = 24);

// Area of the shape itself, m².
double shapeArea(const MarkerShape& shape);

}  // namespace soccer_vision
