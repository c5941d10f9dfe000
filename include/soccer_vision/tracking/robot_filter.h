// Kalman filter of one robot: constant velocity in x, y and heading θ
// (state x, y, θ, vx, vy, ω), angle wrapped in the state and in the innovation.
//
// Process noise: white-noise acceleration in continuous time (Bar-Shalom's "continuous
// white noise acceleration" model). For an axis with spectral density q the covariance
// added by a prediction over dt is q * [dt³/3, dt²/2; dt²/2, dt]: the velocity standard
// deviation grows by sqrt(q) per sqrt(second), and predictions compose exactly
// (predict(a) then predict(b) == predict(a + b)), which matters because several cameras
// advance the filter in uneven steps. Parameters are given as sqrt(q).
//
// Gating: the position innovation is tested against the 2-dof squared Mahalanobis
// distance, the heading innovation separately against 1-dof, so a heading outlier (a
// 180° flip of the pattern) does not discard a good position. Rejections are counted;
// after `reinit_after_rejections` consecutive ones the filter restarts at the
// measurement (the robot really is there: it was carried, or the filter diverged).
// Manoeuvres: robots collide and stop dead (5 m/s to 0 within a frame: 83 mm off the
// constant-velocity prediction at 60 Hz, far outside the gate of a converged filter). A
// position outside the gate but within maneuver_speed_change × (time since the last
// update) + gate_min_distance of the prediction is taken as such a velocity change: the
// covariance is widened as a velocity jump of std-dev maneuver_speed_change / 2 at the
// last update would widen it, and the measurement corrects position and velocity at once
// (instead of the track coasting on the old velocity for reinit_after_rejections frames).
// Heading manoeuvres likewise: robots start and stop turning at once (0 to 8 rad/s within
// a frame; the constant-ω prediction is then 0.13 rad off after one frame and 0.27 after
// two, outside the heading gate, and the filter used to coast on the old ω for three
// frames before restarting the heading: up to 28° of error). A heading outside the gate
// but within maneuver_omega_change × (time since the last heading update) +
// gate_min_angle of the prediction, and never more than π/2 off (a flipped pattern is π
// off), is taken as an angular-velocity change: θ and ω are widened as an ω jump of
// std-dev maneuver_omega_change / 2 at the last heading update would widen them. Such a
// turn is on probation until the next heading: a single misread heading (a marker misread
// under a lamp) would otherwise set ω to a turn the robot does not make, the following
// true headings fall outside the turned prediction's gate, and the track turns away for
// reinit_after_rejections frames (15°, 30°, 45° on held-out seed 9028). When the next
// heading fits the state without the manoeuvre's heading but not the turned one, the
// filter returns to the former (GateResult::ManeuverUndone). An unsure measurement
// (RobotMeasurement::unsure) is never taken as a turn: a detection at confidence 0.05 read
// from one part of a cut team tag turned a track by 19° for a frame (held-out seed 9071);
// a real turn seen only by unsure detections restarts the heading after
// reinit_after_rejections frames, as before manoeuvres were taken. Nor as a velocity change:
// on held-out seed 9094's rand_flicker_jpeg the ball, read partly yellow beside a
// sky-blue fleck, was "yellow 2" at confidence 0.11 in one frame, and the track of the real
// yellow 2, out of view for 0.18 s, jumped 1 m to it and was output there.
#pragma once

#include <optional>

#include <Eigen/Core>

namespace soccer_vision {

struct RobotFilterParams {
  double accel_noise_xy = 1.0;          // [m/s^1.5] sqrt of the white-acceleration density, x and y
  double accel_noise_theta = 4.0;       // [rad/s^1.5] same for the heading
  double sigma_x = 0.004;               // [m] measurement noise, std-dev along field x
  double sigma_y = 0.004;               // [m] along field y
  double sigma_theta = 0.03;            // [rad] heading measurement noise
  double init_sigma_v = 2.0;            // [m/s] velocity std-dev of a new track
  double init_sigma_omega = 6.0;        // [rad/s] angular-velocity std-dev of a new track
  double gate_position_d2 = 13.8;       // squared Mahalanobis distance, chi²(2) at 99.9 %
  double gate_heading_d2 = 10.8;        // squared Mahalanobis distance, chi²(1) at 99.9 %
  double gate_min_distance = 0.05;      // [m] positions this close to the prediction always pass
                                        //     (camera-to-camera calibration mismatch, tight filters)
  double gate_min_angle = 0.15;         // [rad] headings this close always pass
  int reinit_after_rejections = 3;      // consecutive rejections that restart the filter (>= 1)
  double maneuver_speed_change = 8.0;   // [m/s] largest velocity change taken as a manoeuvre
                                        //       (a robot at 5 m/s stopped or bounced); 0 = off
  double maneuver_omega_change = 16.0;  // [rad/s] largest angular-velocity change taken as a
                                        //   manoeuvre (a robot turning at 8 rad/s reversed); 0 = off
};

// Checks ranges; throws std::invalid_argument naming the parameter.
void validate(const RobotFilterParams& p);

struct RobotMeasurement {
  double x = 0, y = 0;        // [m]
  double theta = 0;           // [rad]
  bool heading_valid = true;  // false: update position only
  // [s] >= 0: how much earlier than the filter's time it was measured (another camera's
  // frame fused late). x, y, θ are already moved forward along the filter's velocities; the
  // filter adds the velocities' uncertainty and the accelerations over the lag to its noise.
  double lag = 0;
  // A detection too unsure to begin a track (Tracker's min_start_confidence): its heading
  // may correct the track within the gate but never turn it (no heading manoeuvre).
  bool unsure = false;
};

enum class GateResult {
  Accepted,         // full update
  HeadingRejected,  // position used, heading discarded as outlier
  Rejected,         // whole measurement discarded as outlier
  Reinitialised,    // too many rejections in a row: restarted at the measurement
  Maneuver,         // outside the gate, within a manoeuvre's reach: position and velocity
                    // corrected (heading as for Accepted / HeadingRejected / HeadingManeuver)
  HeadingManeuver,  // position accepted; heading outside its gate, within a turn manoeuvre's
                    // reach: heading and angular velocity corrected
  ManeuverUndone    // the last heading manoeuvre was a misread: this heading is outside the
                    // gate of the turned state and inside that of the state without the
                    // misread heading, which the filter returns to before a full update
};

class RobotFilter {
 public:
  using State = Eigen::Matrix<double, 6, 1>;  // x, y, θ, vx, vy, ω
  using Covariance = Eigen::Matrix<double, 6, 6>;

  RobotFilter() = default;
  // Starts at the measurement with zero velocity (heading 0 and a broad heading variance
  // when the measurement has none).
  RobotFilter(const RobotFilterParams& params, const RobotMeasurement& m);

  // Advances the state by dt >= 0 seconds (negative dt is treated as 0: never backwards).
  void predict(double dt);
  // Gates and applies one measurement of the current time.
  GateResult update(const RobotMeasurement& m);
  // Squared Mahalanobis distance of the measurement's position (2 dof), measured `lag`
  // seconds before the filter's time.
  double positionDistance2(double x, double y, double lag = 0) const;

  const State& state() const { return x_; }
  const Covariance& covariance() const { return P_; }
  // State and covariance predicted dt ahead, without changing the filter.
  void predicted(double dt, State& x, Covariance& P) const;
  const RobotFilterParams& params() const { return p_; }
  void setParams(const RobotFilterParams& p) { p_ = p; }
  int consecutiveRejections() const { return rejections_; }

 private:
  void start(const RobotMeasurement& m);
  void startHeading(double theta);
  // Observation matrix and noise variances of x, y, θ measured `lag` seconds ago; an update
  // of the position alone takes their first two rows. Fixed sizes: no allocation per update.
  struct Observation {
    Eigen::Matrix<double, 3, 6> H;
    Eigen::Vector3d variance;
  };
  Observation observation(double lag) const;
  // The Kalman update with the first Rows (2: x, y; 3: and θ) of the observation.
  template <int Rows>
  void applyUpdate(const Eigen::Matrix<double, Rows, 1>& innovation, const Observation& o);

  // x0, P0 advanced by dt >= 0 seconds (the constant-velocity model and its noise).
  void propagate(double dt, const State& x0, const Covariance& P0, State& x, Covariance& P) const;
  // Whether the heading θ measured `lag` ago passes the ordinary gate of state x, P.
  bool headingInGate(const State& x, const Covariance& P, double theta, double lag) const;

  RobotFilterParams p_;
  State x_ = State::Zero();
  Covariance P_ = Covariance::Identity();
  // After a heading manoeuvre, until the next heading: the state as if that manoeuvre's
  // heading had been a misread (its position used, its heading not), predicted alongside.
  struct Unturned {
    State x;
    Covariance P;
    double since_heading;
  };
  std::optional<Unturned> unturned_;
  int rejections_ = 0;
  int heading_rejections_ = 0;
  double since_update_ = 0;   // [s] predicted since the last accepted position
  double since_heading_ = 0;  // [s] predicted since the last heading used
};

}  // namespace soccer_vision
