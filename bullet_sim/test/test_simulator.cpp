// The simulated laser, motion and odometry against their models.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "bullet_sim/simulator.h"

using namespace bullet_sim;

namespace {

// A closed 6 x 4 m room, walls 0.1 m thick: inner faces at x = 0.05, 5.95 and y = 0.05, 3.95.
const char* kRoom = R"(name: room
walls:
  - points: [[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]
robot:
  start: [3.0, 2.0, 0.0]
)";

// One wall only: most beams see nothing.
const char* kOpen = R"(name: open
walls:
  - points: [[2, -1], [2, 1]]
robot:
  start: [0.0, 0.0, 0.0]
)";

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

RobotModel testRobot() {
  return robotModelFromUrdf(readFile(URDF_PATH), "base_link", "laser");
}

SimParams quietParams() {
  SimParams p;
  p.odom_left_radius_error = p.odom_right_radius_error = p.odom_wheelbase_error = 0.0;
  return p;
}

// Exact distance from (x, y) along angle a to the inside of the room.
double roomDistance(double x, double y, double a) {
  const double dx = std::cos(a), dy = std::sin(a);
  double t = 1e9;
  if (dx > 1e-12) t = std::min(t, (5.95 - x) / dx);
  if (dx < -1e-12) t = std::min(t, (0.05 - x) / dx);
  if (dy > 1e-12) t = std::min(t, (3.95 - y) / dy);
  if (dy < -1e-12) t = std::min(t, (0.05 - y) / dy);
  return t;
}

void drive(Simulator* sim, double v, double w, double seconds) {
  sim->setCommand(v, w);
  const int steps = static_cast<int>(std::lround(seconds * sim->params().physics_rate));
  for (int i = 0; i < steps; ++i) sim->step();
}

}  // namespace

TEST(RobotModel, ReadsFootprintAndLaserFromUrdf) {
  const RobotModel r = testRobot();
  EXPECT_NEAR(r.radius, 0.25, 1e-9);
  EXPECT_NEAR(r.laser_z, 0.3, 1e-9);
  EXPECT_THROW(robotModelFromUrdf(readFile(URDF_PATH), "base_link", "no_such_link"), RobotModelError);
  EXPECT_THROW(robotModelFromUrdf("<robot", "base_link", "laser"), RobotModelError);
}

// The footprint every node keeps clear with (config/robot.yaml) is the one the simulator drives.
TEST(RobotModel, TheSharedFootprintIsTheUrdfs) {
  const YAML::Node robot = YAML::LoadFile(ROBOT_YAML);
  ASSERT_TRUE(robot["radius"].IsDefined()) << "config/robot.yaml has no radius";
  EXPECT_DOUBLE_EQ(robot["radius"].as<double>(), testRobot().radius);
}

TEST(Laser, RangesMatchTheWallsWithinTheNoiseModel) {
  const World world = parseWorld(kRoom, "room");
  const RobotModel robot = testRobot();
  Simulator sim(world, robot, quietParams());
  const LaserGeometry& g = sim.laser();
  std::vector<float> ranges;
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int scan = 0; scan < 20; ++scan) {
    sim.scan(&ranges);
    ASSERT_EQ(ranges.size(), 720u);
    for (int i = 0; i < g.beams; ++i) {
      const double exact = roomDistance(3.0 + robot.laser_x, 2.0 + robot.laser_y, g.angle_min + i * g.angle_increment);
      const double e = ranges[i] - exact;
      ASSERT_LT(std::abs(e), 6 * 0.01) << "beam " << i;
      sum += e;
      sum2 += e * e;
      ++n;
    }
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.001);
  EXPECT_NEAR(sd, 0.01, 0.0007);  // sigma = 1 cm
}

TEST(Laser, BeamCountAndAnglesFollowTheParameters) {
  const World world = parseWorld(kRoom, "room");
  Simulator full(world, testRobot(), quietParams());
  EXPECT_EQ(full.laser().beams, 720);
  EXPECT_NEAR(full.laser().angle_min, -M_PI, 1e-12);
  EXPECT_NEAR(full.laser().angle_increment, 2 * M_PI / 720, 1e-12);
  EXPECT_LT(full.laser().angle_max(), M_PI);  // no repeated beam at +pi

  SimParams p = quietParams();
  p.laser_beams = 181;
  p.laser_fov = M_PI;
  Simulator half(world, testRobot(), p);
  EXPECT_NEAR(half.laser().angle_min, -M_PI / 2, 1e-12);
  EXPECT_NEAR(half.laser().angle_max(), M_PI / 2, 1e-12);
  std::vector<float> ranges;
  half.exactScan(&ranges);
  ASSERT_EQ(ranges.size(), 181u);
  EXPECT_NEAR(ranges[90], 5.95 - 3.0, 1e-4);   // straight ahead
  EXPECT_NEAR(ranges[0], 2.0 - 0.05, 1e-4);    // right (-90°)
  EXPECT_NEAR(ranges[180], 3.95 - 2.0, 1e-4);  // left (+90°)
}

TEST(Laser, NoReturnIsPlusInfAndTooCloseIsMinusInf) {
  const World world = parseWorld(kOpen, "open");
  Simulator sim(world, testRobot(), quietParams());
  std::vector<float> ranges;
  sim.scan(&ranges);
  const LaserGeometry& g = sim.laser();
  int inf = 0, finite = 0;
  for (int i = 0; i < g.beams; ++i) {
    const double a = g.angle_min + i * g.angle_increment;
    if (std::abs(a) < 0.4) {
      EXPECT_TRUE(std::isfinite(ranges[i])) << i;
      ++finite;
    } else if (std::abs(a) > 1.0) {
      EXPECT_TRUE(std::isinf(ranges[i]) && ranges[i] > 0) << i << " " << ranges[i];
      ++inf;
    }
  }
  EXPECT_GT(inf, 400);
  EXPECT_GT(finite, 80);

  SimParams p = quietParams();
  p.laser_range_min = 3.0;  // the wall at 1.95 m is closer than range_min
  Simulator close(world, testRobot(), p);
  close.scan(&ranges);
  EXPECT_TRUE(std::isinf(ranges[360]) && ranges[360] < 0) << ranges[360];
}

// Brute force over every obstacle, with the slab test in each box's own frame (an independent method).
double bruteForceRay(const World& world, double ox, double oy, double dx, double dy, bool* hit_cylinder) {
  double best = std::numeric_limits<double>::infinity();
  *hit_cylinder = false;
  for (const OrientedBox& b : world.solidBoxes()) {
    const double c = std::cos(b.yaw), s = std::sin(b.yaw);
    const double lx = c * (ox - b.center.x) + s * (oy - b.center.y), ly = -s * (ox - b.center.x) + c * (oy - b.center.y);
    const double ldx = c * dx + s * dy, ldy = -s * dx + c * dy;
    double t0 = -1e300, t1 = 1e300;
    const double o[2] = {lx, ly}, d[2] = {ldx, ldy}, h[2] = {b.half_x, b.half_y};
    bool miss = false;
    for (int k = 0; k < 2; ++k) {
      if (std::abs(d[k]) < 1e-15) {
        if (std::abs(o[k]) > h[k]) miss = true;
        continue;
      }
      double a0 = (-h[k] - o[k]) / d[k], a1 = (h[k] - o[k]) / d[k];
      if (a0 > a1) std::swap(a0, a1);
      t0 = std::max(t0, a0);
      t1 = std::min(t1, a1);
    }
    if (!miss && t0 <= t1 && t0 >= 0 && t0 < best) {
      best = t0;
      *hit_cylinder = false;
    }
  }
  for (const Cylinder& cy : world.cylinders) {
    const double fx = ox - cy.center.x, fy = oy - cy.center.y;
    const double b = fx * dx + fy * dy, disc = b * b - (fx * fx + fy * fy - cy.radius * cy.radius);
    if (disc < 0) continue;
    const double t = -b - std::sqrt(disc);
    if (t >= 0 && t < best) {
      best = t;
      *hit_cylinder = true;
    }
  }
  return best;
}

TEST(Laser, TreeRayCasterAgreesWithBruteForceAndBulletRayTest) {
  const World world = loadWorldFile(std::string(WORLDS_DIR) + "/institute.yaml");
  const RayCaster2D caster(world);
  const CollisionWorld bullet(world, 0.25);
  Vec2 lo, hi;
  world.bounds(&lo, &hi);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y), ua(-M_PI, M_PI);
  int compared = 0;
  std::vector<double> bullet_error;
  while (compared < 5000) {
    const Vec2 p{ux(rng), uy(rng)};
    if (distanceToObstacles(world, p) < 0.05) continue;
    const double a = ua(rng), dx = std::cos(a), dy = std::sin(a);
    const double mine = caster.cast(p.x, p.y, dx, dy, 15.0);
    bool cylinder = false;
    double exact = bruteForceRay(world, p.x, p.y, dx, dy, &cylinder);
    if (exact > 15.0) exact = std::numeric_limits<double>::infinity();
    ASSERT_EQ(std::isinf(mine), std::isinf(exact)) << p.x << " " << p.y << " " << a;
    if (!std::isinf(mine)) ASSERT_NEAR(mine, exact, 1e-9) << p.x << " " << p.y << " " << a;
    // Bullet's own ray test (the naive baseline) on boxes; its cylinders are approximated by GJK.
    const double theirs = bullet.rayTest(p.x, p.y, dx, dy, 15.0);
    if (!cylinder && !std::isinf(exact)) bullet_error.push_back(std::abs(mine - theirs));
    ++compared;
  }
  // Bullet's default convex ray cast (subsimplex, float, tolerance relative to the 15 m ray) is itself
  // approximate: most rays agree to a fraction of a millimetre, a few by a few centimetres.
  ASSERT_GT(bullet_error.size(), 4000u);
  std::sort(bullet_error.begin(), bullet_error.end());
  EXPECT_LT(bullet_error[bullet_error.size() / 2], 1e-3) << "median";
  EXPECT_LT(bullet_error[bullet_error.size() * 99 / 100], 5e-2) << "99th percentile";
}

TEST(Motion, DrivingIntoAWallAtTopSpeedStopsAtTheWall) {
  const World world = parseWorld(kRoom, "room");
  for (double speed : {0.6, 5.0, 50.0}) {
    SimParams p = quietParams();
    p.max_linear_velocity = speed;
    p.max_linear_accel = 1000.0;
    Simulator sim(world, testRobot(), p);
    bool bumped = false;
    sim.setCommand(speed, 0.0);
    for (int i = 0; i < 2000; ++i) {
      sim.step();
      bumped |= sim.bumper();
      // The footprint never overlaps the wall (inner face at x = 5.95).
      ASSERT_LE(sim.truePose().x, 5.95 - 0.25 + 1e-6) << "speed " << speed << " step " << i;
    }
    EXPECT_TRUE(bumped) << speed;
    EXPECT_NEAR(sim.truePose().x, 5.95 - 0.25, 0.01) << speed;
    // It can back away from the wall.
    drive(&sim, -0.5, 0.0, 1.0);
    EXPECT_LT(sim.truePose().x, 5.95 - 0.25 - 0.2);
  }
}

TEST(Motion, DiagonalAndFurnitureContactsNeverPenetrate) {
  const World world = loadWorldFile(std::string(WORLDS_DIR) + "/institute.yaml");
  SimParams p = quietParams();
  p.max_linear_velocity = 3.0;
  p.max_angular_velocity = 3.0;
  Simulator sim(world, testRobot(), p);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uw(-3.0, 3.0);
  int contacts = 0;
  for (int i = 0; i < 30000; ++i) {
    if (i % 150 == 0) sim.setCommand(3.0, uw(rng));
    sim.step();
    contacts += sim.bumper();
    ASSERT_GT(distanceToObstacles(world, {sim.truePose().x, sim.truePose().y}), 0.25 - 2e-3) << "step " << i;
  }
  EXPECT_GT(contacts, 0);
}

TEST(Odometry, RandomErrorMatchesTheConfiguredNoise) {
  const World world = parseWorld(R"(name: hall
walls:
  - points: [[-1, -2], [1000, -2]]
robot:
  start: [0.0, 0.0, 0.0]
)", "hall");
  SimParams p = quietParams();
  p.odom_wheel_noise = 0.005;
  Simulator sim(world, testRobot(), p);
  drive(&sim, 0.5, 0.0, 2.0);  // reach speed
  const int segments = 400;
  std::vector<double> ds_err, dth_err;
  for (int k = 0; k < segments; ++k) {
    const Pose2 t0 = sim.truePose(), o0 = sim.odomPose();
    drive(&sim, 0.5, 0.0, 1.0);
    const Pose2 t1 = sim.truePose(), o1 = sim.odomPose();
    const double true_ds = std::hypot(t1.x - t0.x, t1.y - t0.y);
    const double odom_ds = std::hypot(o1.x - o0.x, o1.y - o0.y);
    ds_err.push_back(odom_ds - true_ds);
    dth_err.push_back(std::remainder((o1.yaw - o0.yaw) - (t1.yaw - t0.yaw), 2 * M_PI));
  }
  auto stats = [](const std::vector<double>& v, double* mean, double* sd) {
    double s = 0, s2 = 0;
    for (double x : v) s += x;
    *mean = s / v.size();
    for (double x : v) s2 += (x - *mean) * (x - *mean);
    *sd = std::sqrt(s2 / (v.size() - 1));
  };
  double m, sd;
  // Per 0.5 m: var(ds) = k^2 (|l| + |r|) / 4 = k^2 d / 2; var(dtheta) = k^2 (|l| + |r|) / b^2 = 2 k^2 d / b^2.
  stats(ds_err, &m, &sd);
  EXPECT_NEAR(sd, 0.005 * std::sqrt(0.5 / 2), 0.15 * 0.005 * std::sqrt(0.25)) << "mean " << m;
  EXPECT_NEAR(m, 0.0, 4 * sd / std::sqrt(segments));
  stats(dth_err, &m, &sd);
  const double expected_th = 0.005 * std::sqrt(2 * 0.5) / 0.4;
  EXPECT_NEAR(sd, expected_th, 0.15 * expected_th) << "mean " << m;
  EXPECT_NEAR(m, 0.0, 4 * sd / std::sqrt(segments));
}

TEST(Odometry, CovarianceMatchesMonteCarloSpread) {
  const World world = parseWorld(kOpen, "open");
  const int runs = 300;
  std::vector<Pose2> ends;
  Eigen::Matrix3d predicted;
  for (int run = 0; run < runs; ++run) {
    SimParams p = quietParams();
    p.seed = 100 + run;
    Simulator sim(world, testRobot(), p);
    sim.teleport({-20.0, 0.0, 0.0});
    drive(&sim, 0.5, 0.2, 8.0);  // an arc
    ends.push_back(sim.odomPose());
    predicted = sim.odomCovariance();  // identical for every run: same true motion
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& e : ends) mean += Eigen::Vector3d(e.x, e.y, e.yaw) / runs;
  Eigen::Matrix3d emp = Eigen::Matrix3d::Zero();
  for (const auto& e : ends) {
    const Eigen::Vector3d d = Eigen::Vector3d(e.x, e.y, e.yaw) - mean;
    emp += d * d.transpose() / (runs - 1);
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(emp(i, i), predicted(i, i), 0.25 * predicted(i, i)) << "axis " << i;
}

TEST(Odometry, SystematicErrorsDriftLikeARealRobot) {
  const World world = parseWorld(kOpen, "open");
  SimParams p = quietParams();
  p.odom_wheel_noise = 0.0;
  p.odom_left_radius_error = 0.01;  // the left wheel reports 1% too much
  Simulator straight(world, testRobot(), p);
  straight.teleport({-30.0, 0.0, 0.0});
  drive(&straight, 0.5, 0.0, 20.0);
  const double d = straight.travelled();
  // dtheta = (right - left) / b = -0.01 d / b
  EXPECT_NEAR(straight.odomPose().yaw, -0.01 * d / 0.4, 1e-3);
  EXPECT_NEAR(straight.truePose().yaw, 0.0, 1e-9);

  p.odom_left_radius_error = 0.0;
  p.odom_wheelbase_error = 0.05;  // odometry believes the wheelbase 5% longer: turns look 5% smaller
  Simulator turn(world, testRobot(), p);
  drive(&turn, 0.0, 1.0, 2.0);
  const double true_turn = turn.truePose().yaw;
  EXPECT_NEAR(turn.odomPose().yaw, true_turn / 1.05, 1e-6);
}

TEST(Determinism, SameSeedSameMessagesOtherSeedOtherNoise) {
  const World world = loadWorldFile(std::string(WORLDS_DIR) + "/small_loop.yaml");
  auto run = [&](uint64_t seed, std::vector<float>* all_ranges, std::vector<double>* odom) {
    SimParams p;
    p.seed = seed;
    Simulator sim(world, testRobot(), p);
    std::vector<float> ranges;
    for (int i = 0; i < 3000; ++i) {
      if (i % 200 == 0) sim.setCommand(0.4, (i / 200) % 2 ? 0.5 : -0.3);
      sim.step();
      if (i % 10 == 0) {
        sim.scan(&ranges);
        all_ranges->insert(all_ranges->end(), ranges.begin(), ranges.end());
        odom->push_back(sim.odomPose().x);
        odom->push_back(sim.odomPose().y);
        odom->push_back(sim.odomPose().yaw);
      }
    }
  };
  std::vector<float> a, b, c;
  std::vector<double> oa, ob, oc;
  run(7, &a, &oa);
  run(7, &b, &ob);
  run(8, &c, &oc);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
  EXPECT_EQ(oa, ob);
  EXPECT_NE(oa, oc);
  EXPECT_NE(0, std::memcmp(a.data(), c.data(), a.size() * sizeof(float)));
}

TEST(Services, TeleportIntoAWallIsRefusedAndResetRestarts) {
  const World world = parseWorld(kRoom, "room");
  Simulator sim(world, testRobot(), quietParams());
  EXPECT_FALSE(sim.teleport({0.1, 2.0, 0.0}));
  EXPECT_FALSE(sim.teleport({NAN, 2.0, 0.0}));
  EXPECT_TRUE(sim.teleport({1.0, 1.0, 1.0}));
  EXPECT_NEAR(sim.truePose().x, 1.0, 1e-12);
  EXPECT_NEAR(sim.odomPose().x, 0.0, 1e-12);  // odometry is not told
  drive(&sim, 0.3, 0.0, 1.0);
  sim.reset();
  EXPECT_NEAR(sim.truePose().x, 3.0, 1e-12);
  EXPECT_NEAR(sim.odomPose().x, 0.0, 1e-12);
}

TEST(Params, InvalidParametersAreRefusedByName) {
  const World world = parseWorld(kRoom, "room");
  SimParams p;
  p.laser_beams = 0;
  try {
    Simulator sim(world, testRobot(), p);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("laser_beams"), std::string::npos);
  }
}
