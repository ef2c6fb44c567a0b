// Monte Carlo consistency of the stochastic map in a simulated room (Bar-Shalom's NEES test): over
// 50 runs of a drive with odometry noise drawn from the noise model and line observations drawn
// from their covariances, the mean NEES of the robot pose at the end must lie in the 95 % band of
// chi^2_(3 x runs) / runs, the mean line NEES in that of chi^2_(2 x runs) / runs, and the EKF's
// final pose error must be far below that of odometry alone.
#include "laser_features/chi_square.h"
#include "ekf_local_map/stochastic_map.h"

#include "simulated_room.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace ekf_local_map {
namespace {

using laser_features::compose;
using namespace testing_support;

const Pose2D kSensorMount{0.12, -0.03, 0.05};

struct RunResult {
  double robot_nees = 0.0;
  double mean_robot_nees_over_time = 0.0;
  std::vector<double> line_nees;
  double ekf_position_error = 0.0;
  double ekf_heading_error = 0.0;
  double odometry_position_error = 0.0;
  size_t lines = 0;
  double mean_nis = 0.0;
};

/// One drive: 1.5 turns of a 0.8 m radius circle in 5 cm steps, a scan after every step.
RunResult driveInRoom(uint32_t seed, const StochasticMapParams& params, double odometry_noise_scale) {
  std::mt19937 rng(seed);
  const std::vector<TrueSegment> room = officeRoom();
  OdometryNoise truth_noise = testOdometryNoise();
  OdometryNoise filter_noise = truth_noise;
  truth_noise.inflation = odometry_noise_scale;  // > 1: the filter is told less than the truth
  StochasticMap map(params);
  Pose2D truth{0, 0, 0}, odometry{0, 0, 0};
  UpdateReport report;
  map.update(observeAll(room, truth, kSensorMount, &rng), kSensorMount, &report);
  RunResult result;
  double nis_sum = 0.0;
  int steps = 150;
  for (int step = 0; step < steps; ++step) {
    const Pose2D u = arcIncrement(0.05, 0.0625);
    const Pose2D measured = noisyIncrement(u, truth_noise, &rng);
    truth = compose(truth, u);
    odometry = compose(odometry, measured);
    map.predict(measured, filter_noise.covariance(measured));
    map.update(observeAll(room, truth, kSensorMount, &rng), kSensorMount, &report);
    result.mean_robot_nees_over_time += map.robotNees(truth) / steps;
    nis_sum += report.mean_nis;
  }
  result.mean_nis = nis_sum / steps;
  result.robot_nees = map.robotNees(truth);
  result.lines = map.numLines();
  for (size_t i = 0; i < std::min(map.numLines(), room.size()); ++i) {
    result.line_nees.push_back(map.lineNees(i, room[i].line()));
  }
  result.ekf_position_error = positionError(map.robotPose(), truth);
  result.ekf_heading_error = std::abs(laser_features::normalizeAngle(map.robotPose().theta - truth.theta));
  result.odometry_position_error = positionError(odometry, truth);
  return result;
}

struct MonteCarlo {
  double mean_robot_nees = 0.0;
  double mean_robot_nees_over_time = 0.0;
  double mean_line_nees = 0.0;
  std::vector<double> per_line_nees;
  double mean_ekf_error = 0.0;
  double max_ekf_error = 0.0;
  double mean_odometry_error = 0.0;
  double mean_nis = 0.0;
  bool all_lines_once = true;
};

MonteCarlo monteCarlo(int runs, const StochasticMapParams& params, double odometry_noise_scale = 1.0) {
  MonteCarlo mc;
  const size_t num_lines = officeRoom().size();
  mc.per_line_nees.assign(num_lines, 0.0);
  for (int run = 0; run < runs; ++run) {
    const RunResult r = driveInRoom(uint32_t(1000 + run), params, odometry_noise_scale);
    mc.all_lines_once = mc.all_lines_once && r.lines == num_lines;
    mc.mean_robot_nees += r.robot_nees / runs;
    mc.mean_robot_nees_over_time += r.mean_robot_nees_over_time / runs;
    for (size_t i = 0; i < r.line_nees.size(); ++i) mc.per_line_nees[i] += r.line_nees[i] / runs;
    mc.mean_ekf_error += r.ekf_position_error / runs;
    mc.max_ekf_error = std::max(mc.max_ekf_error, r.ekf_position_error);
    mc.mean_odometry_error += r.odometry_position_error / runs;
    mc.mean_nis += r.mean_nis / runs;
  }
  for (double nees : mc.per_line_nees) mc.mean_line_nees += nees / double(num_lines);
  return mc;
}

/// The two-sided 95 % band of the mean of `runs` chi^2_dof variables.
std::pair<double, double> neesBand(int dof, int runs) {
  return {laser_features::chiSquareQuantile(0.025, dof * runs) / runs, laser_features::chiSquareQuantile(0.975, dof * runs) / runs};
}

constexpr int kRuns = 50;

TEST(Consistency, RobotAndLineNeesInTheChiSquareBand) {
  const MonteCarlo mc = monteCarlo(kRuns, testParams());
  const auto robot_band = neesBand(3, kRuns);
  const auto line_band = neesBand(2, kRuns);
  std::printf("robot NEES at the end: %.3f (band [%.2f, %.2f]); averaged over the drive: %.3f\n",
              mc.mean_robot_nees, robot_band.first, robot_band.second, mc.mean_robot_nees_over_time);
  std::printf("line NEES: %.3f (band [%.2f, %.2f]); per line:", mc.mean_line_nees, line_band.first, line_band.second);
  for (double nees : mc.per_line_nees) std::printf(" %.2f", nees);
  std::printf("\nmean NIS of the matches: %.3f\n", mc.mean_nis);
  std::printf("final position error: EKF %.4f m mean (%.4f max), odometry alone %.4f m mean\n",
              mc.mean_ekf_error, mc.max_ekf_error, mc.mean_odometry_error);

  EXPECT_TRUE(mc.all_lines_once);
  EXPECT_GE(mc.mean_robot_nees, robot_band.first);
  EXPECT_LE(mc.mean_robot_nees, robot_band.second);
  EXPECT_GE(mc.mean_line_nees, line_band.first);
  EXPECT_LE(mc.mean_line_nees, line_band.second);
  EXPECT_LT(mc.mean_ekf_error, 0.01);  // centimetre precision
  EXPECT_LT(mc.mean_ekf_error, 0.2 * mc.mean_odometry_error);
}

TEST(Consistency, AnOverconfidentFilterFailsTheTest) {  // the control: the test can fail
  // The odometry error is three times (in standard deviation) what the filter is told.
  const MonteCarlo mc = monteCarlo(kRuns, testParams(), 9.0);
  const auto robot_band = neesBand(3, kRuns);
  std::printf("overconfident filter: robot NEES %.3f, line NEES %.3f\n", mc.mean_robot_nees, mc.mean_line_nees);
  EXPECT_GT(mc.mean_robot_nees, robot_band.second);
}

}  // namespace
}  // namespace ekf_local_map
