// The stochastic map's filter steps: the O(n) prediction against the dense eq. 8, the stacked
// update against a dense textbook EKF in Joseph form (eqs. 12–17), new lines with their
// cross-covariances (eqs. 9–11), the r-sign flip near the robot, collinear walls of different rooms,
// rejected observations, a teleport (gating failure), growth beyond the preallocated capacity.
#include "ekf_local_map/stochastic_map.h"

#include "laser_features/chi_square.h"
#include "simulated_room.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

namespace ekf_local_map {
namespace {

using laser_features::compose;
using laser_features::normalizeAngle;
using namespace testing_support;

const Pose2D kSensorMount{0.12, -0.03, 0.05};  // laser off the robot's centre, slightly turned

/// A random symmetric positive definite matrix with correlations everywhere.
Eigen::MatrixXd randomCovariance(Eigen::Index n, double scale, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = normal(*rng);
  return scale * (A * A.transpose() / double(n) + 0.1 * Eigen::MatrixXd::Identity(n, n));
}

/// A map of the office room's lines with a random correlated covariance and wide extents.
StochasticMap randomMap(const std::vector<TrueSegment>& segments, const Pose2D& robot, double scale,
                        std::mt19937* rng, StochasticMapParams params = testParams()) {
  std::vector<MapLine> lines;
  for (const TrueSegment& s : segments) {
    MapLine line;
    line.line = s.line();
    line.extent_start = s.a;
    line.extent_end = s.b;
    lines.push_back(line);
  }
  StochasticMap map(params);
  EXPECT_TRUE(map.setState(robot, lines, randomCovariance(Eigen::Index(3 + 2 * lines.size()), scale, rng)));
  return map;
}

Eigen::VectorXd stateDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Eigen::VectorXd d = a - b;
  d(2) = normalizeAngle(d(2));
  for (Eigen::Index i = 3; i < d.size(); i += 2) d(i) = normalizeAngle(d(i));
  return d;
}

// ---- eqs. 7–8 --------------------------------------------------------------------------------

TEST(Predict, EqualsTheDenseCovariancePropagation) {
  std::mt19937 rng(11);
  StochasticMap map = randomMap(officeRoom(), {0.4, -0.2, 0.7}, 1e-3, &rng);
  const Eigen::MatrixXd P = map.covariance();
  const Eigen::VectorXd x = map.state();
  const Pose2D u{0.08, 0.01, 0.12};
  const Eigen::Matrix3d Q = testOdometryNoise().covariance(u);
  ASSERT_TRUE(map.predict(u, Q));

  Eigen::Matrix3d F, G;
  const Pose2D moved = predictRobotPose(map.robotPose(), u, &F, &G);  // (only for the shapes)
  (void)moved;
  predictRobotPose({x(0), x(1), x(2)}, u, &F, &G);
  // Dense eq. 8: P <- F_x P F_x^T + G_x Q G_x^T with F_x = blkdiag(F, I), G_x = [G; 0].
  const Eigen::Index n = P.rows();
  Eigen::MatrixXd Fx = Eigen::MatrixXd::Identity(n, n);
  Fx.topLeftCorner<3, 3>() = F;
  Eigen::MatrixXd Gx = Eigen::MatrixXd::Zero(n, 3);
  Gx.topRows<3>() = G;
  const Eigen::MatrixXd expected = Fx * P * Fx.transpose() + Gx * Q * Gx.transpose();
  EXPECT_LT((map.covariance() - expected).cwiseAbs().maxCoeff(), 1e-15);
  const Pose2D expected_pose = compose({x(0), x(1), x(2)}, u);
  EXPECT_NEAR(map.robotPose().x, expected_pose.x, 1e-15);
  EXPECT_NEAR(map.robotPose().theta, expected_pose.theta, 1e-15);
  EXPECT_EQ((map.state().tail(n - 3) - x.tail(n - 3)).cwiseAbs().maxCoeff(), 0.0);  // lines untouched
}

TEST(Predict, RefusesNonFiniteIncrements) {
  std::mt19937 rng(12);
  StochasticMap map = randomMap(officeRoom(), {0.4, -0.2, 0.7}, 1e-3, &rng);
  const Eigen::MatrixXd P = map.covariance();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(map.predict({nan, 0, 0}, Eigen::Matrix3d::Identity() * 1e-4));
  Eigen::Matrix3d bad_cov = Eigen::Matrix3d::Identity();
  bad_cov(1, 2) = nan;
  EXPECT_FALSE(map.predict({0.1, 0, 0}, bad_cov));
  EXPECT_EQ(map.covariance(), P);
  EXPECT_TRUE(map.state().allFinite());
}

// ---- eqs. 12–17 against a dense textbook EKF -------------------------------------------------

/// The textbook EKF update (eqs. 13–17, Joseph form) on dense matrices, built from the public
/// model functions, for the given (observation, line) pairs.
struct DenseUpdate {
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  double joint_nis = 0.0;
};
/// H, R, nu (eqs. 12-13) and S, K (eqs. 14-15) of a stacked update on dense matrices.
struct DenseTerms {
  Eigen::MatrixXd H, R, S, K;
  Eigen::VectorXd nu;
};
DenseTerms denseTerms(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, const std::vector<LineSegment>& observations,
                      const std::vector<LineMatch>& matches, const Pose2D& mount) {
  const Eigen::Index n = x.size(), k = Eigen::Index(matches.size());
  DenseTerms t;
  t.H = Eigen::MatrixXd::Zero(2 * k, n);
  t.R = Eigen::MatrixXd::Zero(2 * k, 2 * k);
  t.nu.resize(2 * k);
  for (Eigen::Index a = 0; a < k; ++a) {
    const LineMatch& match = matches[size_t(a)];
    const Eigen::Index l = 3 + 2 * Eigen::Index(match.line);
    Eigen::Matrix2d J_line;
    Matrix23d J_robot;
    const Line h = predictLineInSensor({x(l), x(l + 1), {}}, {x(0), x(1), x(2)}, mount, &J_line, &J_robot);  // eq. 12
    const LineInnovation innovation = lineInnovation(observations[match.observation].line, h);              // eq. 13
    t.H.block(2 * a, 0, 2, 3) = innovation.jacobianSign() * J_robot;
    t.H.block(2 * a, l, 2, 2) = innovation.jacobianSign() * J_line;
    t.R.block(2 * a, 2 * a, 2, 2) = observations[match.observation].line.cov;
    t.nu.segment(2 * a, 2) = innovation.nu;
  }
  t.S = t.H * P * t.H.transpose() + t.R;        // eq. 14
  t.K = P * t.H.transpose() * t.S.inverse();    // eq. 15
  return t;
}

DenseUpdate denseJosephUpdate(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                              const std::vector<LineSegment>& observations, const std::vector<LineMatch>& matches,
                              const Pose2D& mount) {
  const DenseTerms t = denseTerms(x, P, observations, matches, mount);
  DenseUpdate result;
  result.x = x + t.K * t.nu;                                                   // eq. 16
  const Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(x.size(), x.size()) - t.K * t.H;
  result.P = I_KH * P * I_KH.transpose() + t.K * t.R * t.K.transpose();        // eq. 17, Joseph form
  result.joint_nis = t.nu.dot(t.S.ldlt().solve(t.nu));
  return result;
}

TEST(Update, EqualsTheDenseJosephFormEkf) {
  std::mt19937 rng(13);
  const Pose2D robot{0.3, 0.4, 0.5};
  StochasticMap map = randomMap(officeRoom(), robot, 1e-4, &rng);
  const Eigen::VectorXd x = map.state();
  const Eigen::MatrixXd P = map.covariance();
  // Observations of lines 0, 2, 3, 5 from a pose near the estimate.
  std::vector<TrueSegment> seen;
  std::vector<size_t> seen_index = {0, 2, 3, 5};
  for (size_t i : seen_index) seen.push_back(officeRoom()[i]);
  const std::vector<LineSegment> observations = observeAll(seen, {0.31, 0.39, 0.505}, kSensorMount, &rng);

  UpdateReport report;
  map.update(observations, kSensorMount, &report);
  ASSERT_EQ(report.matched, 4u);
  ASSERT_EQ(report.new_lines, 0u);
  ASSERT_TRUE(report.fused);

  for (const LineMatch& match : report.matches) EXPECT_EQ(match.line, seen_index[match.observation]);
  const DenseUpdate expected = denseJosephUpdate(x, P, observations, report.matches, kSensorMount);
  EXPECT_LT(stateDifference(map.state(), expected.x).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((map.covariance() - expected.P).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(report.joint_nis, expected.joint_nis, 1e-9);
  EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
}

/// Eqs. 14–17 written out on dense matrices in their plainest form (S = H P H^T + R,
/// K = P H^T S^-1, x + K nu, P - K S K^T), for the given (observation, line) pairs.
DenseUpdate denseTextbookUpdate(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                const std::vector<LineSegment>& observations, const std::vector<LineMatch>& matches,
                                const Pose2D& mount) {
  const DenseTerms t = denseTerms(x, P, observations, matches, mount);
  DenseUpdate result;
  result.x = x + t.K * t.nu;                            // eq. 16
  result.P = P - t.K * t.S * t.K.transpose();           // eq. 17
  result.joint_nis = t.nu.dot(t.S.inverse() * t.nu);
  return result;
}

/// A place of `num_lines` well separated lines: 10 (or all, if fewer) around the origin, seen by
/// the test scans and spread over the state (so that H reaches into every part of P), the others
/// 8-20 m away.
std::vector<TrueSegment> scatteredPlace(size_t num_lines, std::vector<size_t>* seen, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const size_t near = std::min<size_t>(num_lines, 10);
  seen->clear();
  for (size_t q = 0; q < near; ++q) seen->push_back(q * num_lines / near + (q * 7) % std::max<size_t>(num_lines / near, 1));
  std::vector<TrueSegment> segments;
  size_t q = 0;
  for (size_t i = 0; i < num_lines; ++i) {
    const bool is_near = q < near && (*seen)[q] == i;
    const double angle = is_near ? kPi * double(q) / double(near) + 0.05 : kPi * uniform(*rng);
    const double distance = is_near ? 1.0 + 0.3 * double(q) : 8.0 + 12.0 * uniform(*rng);
    const double bearing = is_near ? 2.0 * kPi * double(q) / double(near) + 0.3 : 2.0 * kPi * uniform(*rng);
    q += is_near ? 1 : 0;
    const Eigen::Vector2d centre = distance * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
    const Eigen::Vector2d half = 0.8 * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    segments.push_back({centre - half, centre + half});
  }
  return segments;
}

// The stacked update's kernels (W = P H^T, V = W L^-T with x += V L^-1 nu, P -= V V^T on the lower
// triangle) against the plain dense eqs. 14–17, for state sizes that exercise every row tail and
// block edge of the kernels, with the instruction set `isa` (the caller checked it is available).
void expectKernelsEqualTheDenseTextbookEkf(UpdateKernelIsa isa) {
  for (const size_t num_lines : {3, 4, 10, 37, 61, 120}) {
    SCOPED_TRACE("kernels " + std::to_string(int(isa)) + ", " + std::to_string(num_lines) + " lines");
    std::mt19937 rng(uint32_t(100 + num_lines));
    std::vector<size_t> seen_index;
    const std::vector<TrueSegment> segments = scatteredPlace(num_lines, &seen_index, &rng);
    const Pose2D robot{0.02, -0.01, 0.03};
    StochasticMap map = randomMap(segments, robot, 1e-4, &rng);
    const Eigen::VectorXd x = map.state();
    const Eigen::MatrixXd P = map.covariance();
    std::vector<TrueSegment> seen;
    for (size_t i : seen_index) seen.push_back(segments[i]);
    const std::vector<LineSegment> observations = observeAll(seen, {0.03, -0.015, 0.034}, kSensorMount, &rng);

    UpdateReport report;
    map.update(observations, kSensorMount, &report);
    ASSERT_EQ(report.matched, seen.size());
    ASSERT_EQ(report.new_lines, 0u);
    ASSERT_TRUE(report.fused);
    for (const LineMatch& match : report.matches) EXPECT_EQ(match.line, seen_index[match.observation]);

    const DenseUpdate expected = denseTextbookUpdate(x, P, observations, report.matches, kSensorMount);
    // Relative to the size of the correction (state) and of the covariance.
    const Eigen::VectorXd correction = stateDifference(expected.x, x);
    const double state_error = stateDifference(map.state(), expected.x).cwiseAbs().maxCoeff();
    EXPECT_LE(state_error, 1e-9 * correction.cwiseAbs().maxCoeff());
    const double cov_error = (map.covariance() - expected.P).cwiseAbs().maxCoeff();
    EXPECT_LE(cov_error, 1e-9 * P.cwiseAbs().maxCoeff());
    EXPECT_NEAR(report.joint_nis, expected.joint_nis, 1e-9 * expected.joint_nis);
    EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
  }
}

TEST(Update, PortableKernelsEqualTheDenseTextbookEkf) {
  const UpdateKernelIsa default_isa = updateKernelIsa();
  ASSERT_TRUE(setUpdateKernelIsa(UpdateKernelIsa::kPortable));
  expectKernelsEqualTheDenseTextbookEkf(UpdateKernelIsa::kPortable);
  setUpdateKernelIsa(default_isa);
}

TEST(Update, Avx2FmaKernelsEqualTheDenseTextbookEkf) {
  const UpdateKernelIsa default_isa = updateKernelIsa();
  if (!setUpdateKernelIsa(UpdateKernelIsa::kAvx2Fma)) GTEST_SKIP() << "this CPU has no AVX2 and FMA";
  expectKernelsEqualTheDenseTextbookEkf(UpdateKernelIsa::kAvx2Fma);
  setUpdateKernelIsa(default_isa);
}

TEST(Update, ALineWhoseRCrossesZeroIsCanonicalizedWithItsCovariance) {
  // A map line 0.5 mm from the place origin (where the robot is), correlated with everything; the
  // observation puts it 4 mm on the other side: the posterior r < 0 is brought back to r >= 0 by
  // (alpha + pi, -r), which negates r's row and column of P.
  // (The line sits in the middle of the state, so that r has both a row and a column part.)
  std::mt19937 rng(31);
  std::vector<TrueSegment> segments = officeRoom();
  segments.resize(4);
  segments.insert(segments.begin() + 2, TrueSegment{{-2.0, 0.0005}, {3.0, 0.0005}});
  const Pose2D mount{0.0, 0.0, 0.0};
  StochasticMap map = randomMap(segments, {0.0, 0.0, 0.0}, 1e-4, &rng);
  const Eigen::VectorXd x = map.state();
  const Eigen::MatrixXd P = map.covariance();
  const Eigen::Index l = 3 + 2 * 2;
  ASSERT_NEAR(x(l + 1), 0.0005, 1e-12);

  std::vector<TrueSegment> seen = segments;
  seen[2] = {{-2.0, -0.004}, {3.0, -0.004}};
  const std::vector<LineSegment> observations = observeAll(seen, {0.0, 0.0, 0.0}, mount, nullptr);
  UpdateReport report;
  map.update(observations, mount, &report);
  ASSERT_EQ(report.matched, 5u);

  DenseUpdate expected = denseJosephUpdate(x, P, observations, report.matches, mount);
  ASSERT_LT(expected.x(l + 1), 0.0) << "the test needs the update to push r below zero";
  expected.x(l) = normalizeAngle(expected.x(l) + kPi);
  expected.x(l + 1) = -expected.x(l + 1);
  Eigen::VectorXd flip = Eigen::VectorXd::Ones(x.size());
  flip(l + 1) = -1.0;
  expected.P = flip.asDiagonal() * expected.P * flip.asDiagonal();

  EXPECT_GE(map.line(2).line.r, 0.0);
  EXPECT_LT(stateDifference(map.state(), expected.x).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((map.covariance() - expected.P).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(Update, CommonHeadingErrorIsJointlyCompatible) {
  // The prediction is 2.8 sigma off in heading: every line's innovation lies outside its
  // individual gate, but together they are one 2.8 sigma error of one state: jointly compatible.
  // Fusing them is right; calling it a gating failure would lose the robot for nothing.
  std::mt19937 rng(32);
  StochasticMap map(testParams());
  map.update(observeAll(officeRoom(), {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
  const double sigma_theta = 0.01;
  map.predict({0.0, 0.0, 0.028}, Eigen::Vector3d(1e-6, 1e-6, sigma_theta * sigma_theta).asDiagonal());
  UpdateReport report;
  map.update(observeAll(officeRoom(), {0, 0, 0}, kSensorMount, nullptr), kSensorMount, &report);
  EXPECT_FALSE(report.gating_failure);
  EXPECT_EQ(report.matched, officeRoom().size());
  for (const LineMatch& match : report.matches) EXPECT_GT(match.nis, 5.991);  // each outside its gate
  EXPECT_LT(std::abs(map.robotPose().theta), 0.003);
  EXPECT_EQ(map.numLines(), officeRoom().size());
}

TEST(Update, PairsLostWithAnOutlierAreRecoveredAgainstThePosterior) {
  // A 3.2 sigma heading error, two imprecise walls, and a shelf that was moved 2.5 cm: the moved
  // shelf spoils the joint test, so only the individually gated pairs (the imprecise walls among
  // them) are fused; the others, out of their gates against the prior, match in the second pass
  // against the posterior. The shelf stays unexplained: ambiguous, neither fused nor added.
  const Pose2D mount = kSensorMount;
  StochasticMap map(testParams());
  map.update(observeAll(officeRoom(), {0, 0, 0}, mount, nullptr), mount, nullptr);
  map.predict({0.0, 0.0, 0.016}, Eigen::Vector3d(1e-6, 1e-6, 0.005 * 0.005).asDiagonal());
  std::vector<LineSegment> observations;
  for (size_t i = 0; i < officeRoom().size(); ++i) {
    TrueSegment segment = officeRoom()[i];
    if (i == 5) segment.a.x() += 0.025, segment.b.x() += 0.025;
    observations.push_back(observeSegment(segment, i, mount, nullptr, (i == 0 || i == 3) ? 4.0 : 1.0));
  }
  UpdateReport report;
  map.update(observations, mount, &report);
  EXPECT_EQ(report.matched, 6u);
  EXPECT_EQ(report.outcomes[5], ObservationOutcome::kAmbiguous);
  EXPECT_EQ(report.new_lines, 0u);
  EXPECT_LT(std::abs(map.robotPose().theta), 0.003);
}

TEST(Update, EachLineIsUsedAtMostOncePerScan) {
  // The bottom wall seen as two collinear pieces (a cupboard in front of its middle): the closer
  // match is fused, the other piece is ambiguous (neither fused a second time nor a new line).
  std::mt19937 rng(34);
  StochasticMap map(testParams());
  map.update(observeAll(officeRoom(), {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
  std::vector<TrueSegment> seen = officeRoom();
  seen[0] = {{-2.5, -1.5}, {0.0, -1.5}};
  seen.push_back({{0.8, -1.5}, {3.5, -1.5}});
  UpdateReport report;
  map.update(observeAll(seen, {0, 0, 0}, kSensorMount, &rng), kSensorMount, &report);
  size_t uses_of_wall = 0;
  for (const LineMatch& match : report.matches) uses_of_wall += match.line == 0 ? 1 : 0;
  EXPECT_EQ(uses_of_wall, 1u);
  EXPECT_EQ(report.matched, officeRoom().size());
  EXPECT_EQ(report.ambiguous, 1u);
  EXPECT_EQ(report.new_lines, 0u);
  EXPECT_EQ(map.numLines(), officeRoom().size());
}

TEST(Update, SensorOnALineThroughThePlaceOriginStaysConsistent) {
  // The sensor drives along a line that passes through it and through the place origin (r ~ 0 in
  // both frames): observations and predictions keep switching between (alpha, r) and
  // (alpha + pi, -r), and so does the map line. Over 50 runs the line's NEES must stay in the
  // chi^2_2 band: a wrong Jacobian sign for the flipped innovation sends it above 100.
  std::vector<TrueSegment> segments = officeRoom();
  segments.resize(4);
  segments.push_back({{-2.0, 0.0}, {3.0, 0.0}});
  const OdometryNoise noise = testOdometryNoise();
  const Pose2D mount{0.0, 0.0, 0.0};
  const int runs = 50;
  double line_nees = 0.0;
  for (int run = 0; run < runs; ++run) {
    std::mt19937 rng(300 + run);
    StochasticMap map(testParams());
    Pose2D truth{0, 0, 0};
    map.update(observeAll(segments, truth, mount, &rng), mount, nullptr);
    for (int step = 0; step < 60; ++step) {
      const Pose2D u = arcIncrement(0.01, 0.0);
      truth = compose(truth, u);
      map.predict(noisyIncrement(u, noise, &rng), noise.covariance(u));
      map.update(observeAll(segments, truth, mount, &rng), mount, nullptr);
    }
    ASSERT_EQ(map.numLines(), segments.size()) << "run " << run;
    EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
    line_nees += map.lineNees(4, segments[4].line()) / runs;
  }
  std::printf("line through the sensor and the origin: mean NEES %.2f\n", line_nees);
  EXPECT_GT(line_nees, laser_features::chiSquareQuantile(0.025, 2 * runs) / runs);
  EXPECT_LT(line_nees, laser_features::chiSquareQuantile(0.975, 2 * runs) / runs);
}

// ---- eqs. 9–11 -------------------------------------------------------------------------------

TEST(Update, NewLinesCarryTheirCrossCovariances) {
  std::mt19937 rng(14);
  const std::vector<TrueSegment> room = officeRoom();
  const std::vector<TrueSegment> known(room.begin(), room.begin() + 4);
  StochasticMap map = randomMap(known, {0.2, 0.1, -0.3}, 1e-4, &rng);
  const Eigen::VectorXd x = map.state();
  const Eigen::MatrixXd P = map.covariance();
  // One new segment (the shelf), seen alone.
  const Pose2D sensor_pose = compose(map.robotPose(), kSensorMount);
  const std::vector<LineSegment> observations = {observeSegment(room[5], 5, sensor_pose, &rng)};
  UpdateReport report;
  map.update(observations, kSensorMount, &report);
  ASSERT_EQ(report.new_lines, 1u);
  ASSERT_EQ(map.numLines(), 5u);

  Eigen::Matrix2d J_z;
  Matrix23d J_r;
  const Line expected = lineFromSensorToPlace(observations[0].line, {x(0), x(1), x(2)}, kSensorMount, &J_z, &J_r);
  const Eigen::Index n = P.rows();
  const Eigen::MatrixXd Pn = map.covariance();
  EXPECT_NEAR(map.line(4).line.alpha, expected.alpha, 1e-12);  // eq. 9
  EXPECT_NEAR(map.line(4).line.r, expected.r, 1e-12);
  const Eigen::Matrix2d P_new = J_r * P.topLeftCorner<3, 3>() * J_r.transpose() +
                                J_z * observations[0].line.cov * J_z.transpose();
  EXPECT_LT((Pn.block(n, n, 2, 2) - P_new).cwiseAbs().maxCoeff(), 1e-15);                        // eq. 10
  EXPECT_LT((Pn.block(n, 0, 2, n) - J_r * P.topRows(3)).cwiseAbs().maxCoeff(), 1e-15);           // eq. 11
  EXPECT_LT((Pn.topLeftCorner(n, n) - P).cwiseAbs().maxCoeff(), 0.0 + 1e-300);                     // rest unchanged
  EXPECT_TRUE(positiveSemiDefinite(Pn));
  // The extent is the observed segment in the place frame.
  EXPECT_NEAR(map.line(4).length(), (room[5].b - room[5].a).norm(), 0.02);
}

TEST(Update, GrowsBeyondThePreallocatedCapacity) {
  StochasticMapParams params = testParams();
  params.initial_line_capacity = 2;
  StochasticMap map(params);
  std::mt19937 rng(15);
  map.update(observeAll(officeRoom(), {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
  EXPECT_EQ(map.numLines(), officeRoom().size());
  for (size_t i = 0; i < map.numLines(); ++i) {
    EXPECT_LT(map.lineNees(i, officeRoom()[i].line()), 20.0) << "line " << i;
  }
  EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
}

// ---- the r-sign flip -------------------------------------------------------------------------

TEST(Update, LinePassingThroughTheRobotStaysOneLine) {
  // A low edge (e.g. a step or a glass balustrade base) along y = 0.004 that the robot drives
  // across: seen from below, on top of, and above it; alpha jumps between -pi/2 and pi/2 in the
  // sensor frame and (r ~ 0.004) possibly in the place frame.
  std::vector<TrueSegment> segments = officeRoom();
  segments.resize(4);
  segments.push_back({{-2.0, 0.004}, {3.0, 0.004}});
  const size_t edge = 4;
  const OdometryNoise noise = testOdometryNoise();
  const Pose2D mount{0.0, 0.0, 0.0};  // the laser centre itself crosses the line
  for (int seed = 0; seed < 10; ++seed) {
    std::mt19937 rng(100 + seed);
    StochasticMap map(testParams());
    Pose2D truth{0.0, -0.4, 0.5 * kPi};  // facing +y, below the edge
    ASSERT_TRUE(map.setState(truth, {}, Eigen::Matrix3d::Zero()));  // the place frame is not the start pose here
    map.update(observeAll(segments, truth, mount, &rng), mount, nullptr);
    ASSERT_EQ(map.numLines(), segments.size());
    for (int step = 0; step < 40; ++step) {  // 0.02 m per step: from y = -0.4 to y = +0.4
      const Pose2D u = arcIncrement(0.02, 0.0);
      truth = compose(truth, u);
      map.predict(noisyIncrement(u, noise, &rng), noise.covariance(u));
      UpdateReport report;
      map.update(observeAll(segments, truth, mount, &rng), mount, &report);
      ASSERT_EQ(map.numLines(), segments.size()) << "seed " << seed << " step " << step << ": a duplicate line";
      EXPECT_GE(report.matched, segments.size() - 2) << "seed " << seed << " step " << step;
    }
    EXPECT_LT(map.lineNees(edge, segments[edge].line()), 16.0) << "seed " << seed;
    EXPECT_LT(map.robotNees(truth), 20.0) << "seed " << seed;
    EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
    EXPECT_GE(map.line(edge).line.r, 0.0);
  }
}

// ---- collinear walls of different rooms ------------------------------------------------------

/// A 14 m long place with two collinear wall pieces on y = 3 (x in [0, 4] and [8, 12]), a long
/// wall on y = -1 and end walls.
std::vector<TrueSegment> twoRoomsInARow() {
  return {
      {{-1.0, -1.0}, {13.0, -1.0}},
      {{-1.0, -1.0}, {-1.0, 3.0}},
      {{13.0, -1.0}, {13.0, 3.0}},
      {{0.0, 3.0}, {4.0, 3.0}},
      {{8.0, 3.0}, {12.0, 3.0}},
  };
}

/// Drives along y = 1 from x = 0 to x = 10, seeing the first wall piece from x < 5 and the second
/// from x > 5. Returns the map.
StochasticMap driveAlongCollinearWalls(const StochasticMapParams& params, std::mt19937* rng) {
  const std::vector<TrueSegment> world = twoRoomsInARow();
  const OdometryNoise noise = testOdometryNoise();
  StochasticMap map(params);
  Pose2D truth{0.0, 0.0, 0.0};
  for (int step = 0; step <= 100; ++step) {
    if (step > 0) {
      const Pose2D u = arcIncrement(0.1, 0.0);
      truth = compose(truth, u);
      map.predict(noisyIncrement(u, noise, rng), noise.covariance(u));
    }
    std::vector<TrueSegment> visible = {world[0], world[1], world[2]};
    visible.push_back(truth.x < 5.0 ? world[3] : world[4]);
    map.update(observeAll(visible, truth, kSensorMount, rng), kSensorMount, nullptr);
  }
  return map;
}

TEST(Update, CollinearWallsOfDifferentRoomsAreNotMerged) {
  std::mt19937 rng(16);
  StochasticMap map = driveAlongCollinearWalls(testParams(), &rng);
  ASSERT_EQ(map.numLines(), 5u);
  // Lines 3 and 4 are the two pieces: the same infinite line, disjoint extents.
  const MapLine first = map.line(3), second = map.line(4);
  EXPECT_LT(laser_features::lineMahalanobisSq(first.line, second.line), 5.991);
  EXPECT_NEAR(std::min(first.extent_start.x(), first.extent_end.x()), 0.0, 0.1);
  EXPECT_NEAR(std::max(first.extent_start.x(), first.extent_end.x()), 4.0, 0.1);
  EXPECT_NEAR(std::min(second.extent_start.x(), second.extent_end.x()), 8.0, 0.1);
  EXPECT_NEAR(std::max(second.extent_start.x(), second.extent_end.x()), 12.0, 0.1);

  // Seen together, each piece matches its own line.
  const std::vector<TrueSegment> world = twoRoomsInARow();
  const Pose2D here = map.robotPose();
  UpdateReport report;
  map.update(observeAll(world, here, kSensorMount, &rng), kSensorMount, &report);
  EXPECT_EQ(report.new_lines, 0u);
  for (const LineMatch& match : report.matches) EXPECT_EQ(match.line, match.observation);
  EXPECT_EQ(report.matched, 5u);
}

TEST(Update, CollinearWallsMergeWithoutTheExtentCheck) {  // the control: the check is what separates them
  std::mt19937 rng(16);
  StochasticMapParams params = testParams();
  params.extent_margin = 1e3;
  const StochasticMap map = driveAlongCollinearWalls(params, &rng);
  EXPECT_EQ(map.numLines(), 4u);
}

// ---- bad input -------------------------------------------------------------------------------

TEST(Update, RejectsNonFiniteAndNonPositiveDefiniteObservations) {
  std::mt19937 rng(17);
  StochasticMap map = randomMap(officeRoom(), {0.0, 0.0, 0.0}, 1e-4, &rng);
  const Eigen::VectorXd x = map.state();
  const Eigen::MatrixXd P = map.covariance();
  std::vector<LineSegment> observations = observeAll(officeRoom(), {0, 0, 0}, kSensorMount, &rng);
  observations.resize(3);
  observations[0].line.alpha = std::numeric_limits<double>::quiet_NaN();
  observations[1].line.cov << 1e-5, 3e-5, 3e-5, 1e-5;  // indefinite
  observations[2].line.cov(1, 1) = -1e-6;
  UpdateReport report;
  map.update(observations, kSensorMount, &report);
  EXPECT_EQ(report.rejected_not_finite, 1u);
  EXPECT_EQ(report.rejected_not_positive_definite, 2u);
  EXPECT_EQ(report.outcomes[0], ObservationOutcome::kRejectedNotFinite);
  EXPECT_EQ(report.outcomes[1], ObservationOutcome::kRejectedCovarianceNotPD);
  EXPECT_EQ(report.matched + report.new_lines, 0u);
  EXPECT_FALSE(report.fused);
  EXPECT_EQ(map.state(), x);
  EXPECT_EQ(map.covariance(), P);

  // Mixed with good observations: the good ones are fused, the bad ones still rejected.
  std::vector<LineSegment> mixed = observeAll(officeRoom(), {0, 0, 0}, kSensorMount, &rng);
  mixed[2].line.r = std::numeric_limits<double>::infinity();
  mixed[4].line.cov.setZero();
  map.update(mixed, kSensorMount, &report);
  EXPECT_EQ(report.matched, officeRoom().size() - 2);
  EXPECT_EQ(report.rejected_not_finite + report.rejected_not_positive_definite, 2u);
  EXPECT_TRUE(map.state().allFinite());
  EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
}

/// Builds the office room's map by a short drive; returns the true pose at the end.
Pose2D buildOfficeMap(StochasticMap* map, std::mt19937* rng, int steps = 60) {
  const OdometryNoise noise = testOdometryNoise();
  Pose2D truth{0, 0, 0};
  map->update(observeAll(officeRoom(), truth, kSensorMount, rng), kSensorMount, nullptr);
  for (int step = 0; step < steps; ++step) {
    const Pose2D u = arcIncrement(0.05, 0.0625);
    truth = compose(truth, u);
    map->predict(noisyIncrement(u, noise, rng), noise.covariance(u));
    map->update(observeAll(officeRoom(), truth, kSensorMount, rng), kSensorMount, nullptr);
  }
  return truth;
}

TEST(Update, TeleportIsAGatingFailureAndLeavesTheStateAlone) {
  std::mt19937 rng(18);
  StochasticMap map(testParams());
  Pose2D truth = buildOfficeMap(&map, &rng);
  ASSERT_EQ(map.numLines(), officeRoom().size());
  const Eigen::VectorXd x = map.state();
  const Eigen::MatrixXd P = map.covariance();

  // Kidnapped: 2 m away and turned by 90 degrees, odometry not told.
  truth = {truth.x + 2.0, truth.y - 0.3, normalizeAngle(truth.theta + 0.5 * kPi)};
  UpdateReport report;
  map.update(observeAll(officeRoom(), truth, kSensorMount, &rng), kSensorMount, &report);
  EXPECT_TRUE(report.gating_failure);
  EXPECT_EQ(report.matched, 0u);
  EXPECT_EQ(report.new_lines, 0u);
  EXPECT_FALSE(report.fused);
  EXPECT_GE(report.expected_lines, 3u);  // (some predicted walls lie behind real ones: hidden)
  EXPECT_EQ(map.state(), x);
  EXPECT_EQ(map.covariance(), P);
  EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
  EXPECT_EQ(map.numLines(), officeRoom().size());

  // Keeps failing (and never diverging) while the robot drives on, lost.
  const OdometryNoise noise = testOdometryNoise();
  for (int step = 0; step < 20; ++step) {
    const Pose2D u = arcIncrement(0.05, 0.0);
    truth = compose(truth, u);
    map.predict(noisyIncrement(u, noise, &rng), noise.covariance(u));
    map.update(observeAll(officeRoom(), truth, kSensorMount, &rng), kSensorMount, &report);
    EXPECT_TRUE(report.gating_failure || report.matched <= 1) << "step " << step;
    EXPECT_TRUE(map.state().allFinite());
    EXPECT_TRUE(positiveSemiDefinite(map.covariance()));
  }

  // Relocated at the true pose (e.g. by the topological layer), the filter locks on again.
  map.relocate(truth, Eigen::Vector3d(0.04, 0.04, 0.01).asDiagonal());
  map.update(observeAll(officeRoom(), truth, kSensorMount, &rng), kSensorMount, &report);
  EXPECT_TRUE(report.relocation_attempted);
  EXPECT_TRUE(report.relocation.success()) << toString(report.relocation.verdict);
  EXPECT_LT(positionError(map.robotPose(), truth), 0.02);
  EXPECT_LT(map.robotNees(truth), 20.0);
  EXPECT_FALSE(map.relocationPending());
}

TEST(Update, KnownLinesHiddenBehindNewOnesAreNotAGatingFailure) {
  // The place's known lines (a cabinet, x in [5, 6]) are hidden behind a new wall at x = 3 that the
  // robot sees together with other new lines: a new part of the place, not a teleport.
  const std::vector<TrueSegment> cabinet = {
      {{5.0, -0.5}, {5.0, 0.5}}, {{5.0, 0.5}, {6.0, 0.5}}, {{6.0, 0.5}, {6.0, -0.5}}, {{6.0, -0.5}, {5.0, -0.5}}};
  const std::vector<TrueSegment> new_part = {
      {{3.0, -4.0}, {3.0, 4.0}}, {{-3.0, -2.0}, {3.0, -2.0}}, {{-3.0, 2.0}, {3.0, 2.0}}};
  std::mt19937 rng(21);
  StochasticMap map(testParams());
  ASSERT_TRUE(map.setState({4.0, 0.0, 0.0}, {}, Eigen::Matrix3d::Zero()));
  map.update(observeAll(cabinet, {4.0, 0.0, 0.0}, kSensorMount, &rng), kSensorMount, nullptr);
  ASSERT_EQ(map.numLines(), 4u);
  std::vector<MapLine> cabinet_lines;
  for (size_t i = 0; i < map.numLines(); ++i) cabinet_lines.push_back(map.line(i));
  const Eigen::MatrixXd cabinet_cov = map.covariance();
  ASSERT_TRUE(map.setState({0.0, 0.0, 0.0}, cabinet_lines, cabinet_cov));  // the robot has moved on

  UpdateReport report;
  map.update(observeAll(new_part, {0.0, 0.0, 0.0}, kSensorMount, &rng), kSensorMount, &report);
  EXPECT_FALSE(report.gating_failure);
  EXPECT_EQ(report.expected_lines, 0u);
  EXPECT_EQ(report.new_lines, 3u);

  // The control: without the hiding wall, the cabinet should have been seen: a gating failure.
  StochasticMap control(testParams());
  ASSERT_TRUE(control.setState({0.0, 0.0, 0.0}, cabinet_lines, cabinet_cov));
  std::vector<TrueSegment> open_part(new_part.begin() + 1, new_part.end());
  open_part.push_back({{-3.0, -2.0}, {-3.0, 2.0}});
  control.update(observeAll(open_part, {0.0, 0.0, 0.0}, kSensorMount, &rng), kSensorMount, &report);
  EXPECT_TRUE(report.gating_failure);
  EXPECT_EQ(report.expected_lines, 4u);
  EXPECT_EQ(report.new_lines, 0u);
}

TEST(Update, EmptyScanChangesNothing) {
  std::mt19937 rng(19);
  StochasticMap map = randomMap(officeRoom(), {0.0, 0.0, 0.0}, 1e-4, &rng);
  const Eigen::MatrixXd P = map.covariance();
  UpdateReport report;
  map.update({}, kSensorMount, &report);
  EXPECT_FALSE(report.gating_failure);  // nothing seen is not a contradiction
  EXPECT_EQ(map.covariance(), P);
}

TEST(Update, ReobservationsOutsideTheGateAreNotDuplicated) {
  // 5 % of correct re-observations fall outside the 0.95 gate; they must not become new lines.
  // Also, about once in 100 scans the odometry error is large enough (> 3 sigma) to push the
  // re-observations beyond even the exclusion gate of the prior; the joint test and the second
  // pass against the posterior must catch those too.
  for (int seed = 0; seed < 30; ++seed) {
    std::mt19937 rng(200 + seed);
    StochasticMap map(testParams());
    buildOfficeMap(&map, &rng, 200);
    EXPECT_EQ(map.numLines(), officeRoom().size()) << "seed " << seed;
  }
}

}  // namespace
}  // namespace ekf_local_map
