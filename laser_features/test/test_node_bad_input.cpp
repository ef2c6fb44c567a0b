// rostest: the node answers every bad scan with an empty, finite feature set (or, for a frame with
// no transform, with nothing) and keeps working.
#include <gtest/gtest.h>
#include <hybrid_slam_msgs/LaserFeatures.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>

#include <cmath>
#include <limits>
#include <map>
#include <mutex>

namespace {

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    pub_ = nh_.advertise<sensor_msgs::LaserScan>("scan", 100);
    sub_ = nh_.subscribe("features", 100, &BadInput::onFeatures, this);
    spinner_.start();
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
    while (pub_.getNumSubscribers() == 0 || sub_.getNumPublishers() == 0) {
      ASSERT_LT(ros::WallTime::now(), deadline) << "laser_features_node did not connect";
      ros::WallDuration(0.05).sleep();
    }
    // The node needs the static transform before it accepts scans: send good scans until one passes.
    while (!answered(good(), 0.5)) ASSERT_LT(ros::WallTime::now(), deadline) << "no features for a good scan";
  }

  void onFeatures(const hybrid_slam_msgs::LaserFeatures& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    received_[m.header.stamp.toNSec()] = m;
  }

  // A 720-beam scan of a 6 x 4 m room from its centre.
  sensor_msgs::LaserScan good() {
    sensor_msgs::LaserScan s;
    s.header.frame_id = "laser";
    s.header.stamp = ros::Time(++stamp_);
    s.angle_min = -M_PI;
    s.angle_increment = 2 * M_PI / 720;
    s.angle_max = s.angle_min + 719 * s.angle_increment;
    s.range_min = 0.1;
    s.range_max = 15.0;
    for (int i = 0; i < 720; ++i) {
      const double a = s.angle_min + i * s.angle_increment;
      const double tx = std::abs(std::cos(a)) > 1e-9 ? 3.0 / std::abs(std::cos(a)) : 1e9;
      const double ty = std::abs(std::sin(a)) > 1e-9 ? 2.0 / std::abs(std::sin(a)) : 1e9;
      s.ranges.push_back(static_cast<float>(std::min(tx, ty)));
    }
    return s;
  }

  // Publishes `scan` and waits up to `timeout` s for features with its stamp.
  bool answered(const sensor_msgs::LaserScan& scan, double timeout, hybrid_slam_msgs::LaserFeatures* out = nullptr) {
    pub_.publish(scan);
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = received_.find(scan.header.stamp.toNSec());
        if (it != received_.end()) {
          if (out) *out = it->second;
          return true;
        }
      }
      ros::WallDuration(0.01).sleep();
    }
    return false;
  }

  static void expectFinite(const hybrid_slam_msgs::LaserFeatures& f) {
    for (const auto& l : f.lines) {
      EXPECT_TRUE(std::isfinite(l.alpha) && std::isfinite(l.r));
      for (double c : l.covariance) EXPECT_TRUE(std::isfinite(c));
    }
    for (const auto& c : f.corners) EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.theta));
    for (const auto& o : f.openings) EXPECT_TRUE(std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.width));
    EXPECT_TRUE(std::isfinite(f.place_type_confidence));
  }

  void expectEmptyAnswer(const sensor_msgs::LaserScan& scan, const char* what) {
    hybrid_slam_msgs::LaserFeatures f;
    ASSERT_TRUE(answered(scan, 5.0, &f)) << what << ": no answer (did the node die?)";
    EXPECT_TRUE(f.lines.empty() && f.corners.empty() && f.openings.empty()) << what;
    expectFinite(f);
    // Still alive and right afterwards.
    hybrid_slam_msgs::LaserFeatures ok;
    ASSERT_TRUE(answered(good(), 5.0, &ok)) << "after " << what;
    EXPECT_EQ(ok.lines.size(), 4u) << "after " << what;
  }

  ros::NodeHandle nh_;
  ros::Publisher pub_;
  ros::Subscriber sub_;
  ros::AsyncSpinner spinner_{1};
  std::mutex mutex_;
  std::map<uint64_t, hybrid_slam_msgs::LaserFeatures> received_;
  int stamp_ = 1000;
};

TEST_F(BadInput, GoodScanGivesTheFourWalls) {
  hybrid_slam_msgs::LaserFeatures f;
  ASSERT_TRUE(answered(good(), 5.0, &f));
  EXPECT_EQ(f.lines.size(), 4u);
  EXPECT_EQ(f.corners.size(), 4u);
  EXPECT_EQ(f.header.frame_id, "laser");
  expectFinite(f);
}

TEST_F(BadInput, EmptyScan) {
  auto s = good();
  s.ranges.clear();
  expectEmptyAnswer(s, "empty scan");
}

TEST_F(BadInput, AllNaN) {
  auto s = good();
  for (float& r : s.ranges) r = std::numeric_limits<float>::quiet_NaN();
  expectEmptyAnswer(s, "all NaN");
}

TEST_F(BadInput, AllPlusInf) {
  auto s = good();
  for (float& r : s.ranges) r = std::numeric_limits<float>::infinity();
  expectEmptyAnswer(s, "all +inf");
}

TEST_F(BadInput, RangesNotMatchingTheAngles) {
  auto s = good();
  s.ranges.resize(500);
  expectEmptyAnswer(s, "ranges length not matching angle_min/max/increment");
}

TEST_F(BadInput, ZeroAndNegativeIncrement) {
  auto s = good();
  s.angle_increment = 0.0f;
  expectEmptyAnswer(s, "zero increment");
  auto n = good();
  n.angle_increment = -n.angle_increment;  // sign disagrees with angle_max - angle_min
  expectEmptyAnswer(n, "negative increment with angle_max > angle_min");
}

TEST_F(BadInput, AngleMaxBelowAngleMin) {
  auto s = good();
  std::swap(s.angle_min, s.angle_max);
  expectEmptyAnswer(s, "angle_max < angle_min");
}

TEST_F(BadInput, HundredThousandBeams) {
  auto s = good();
  s.ranges.assign(100000, 2.0f);
  s.angle_increment = static_cast<float>(2 * M_PI / 100000);
  s.angle_max = s.angle_min + 99999 * s.angle_increment;
  expectEmptyAnswer(s, "100,000 beams");
}

TEST_F(BadInput, EveryRangeZero) {
  auto s = good();
  for (float& r : s.ranges) r = 0.0f;
  expectEmptyAnswer(s, "every range 0");
}

TEST_F(BadInput, SingleBeam) {
  auto s = good();
  s.ranges.assign(1, 2.0f);
  s.angle_max = s.angle_min;
  expectEmptyAnswer(s, "single beam");
}

TEST_F(BadInput, FrameWithNoTransformIsSkipped) {
  auto s = good();
  s.header.frame_id = "nowhere";
  EXPECT_FALSE(answered(s, 1.0)) << "features published for a scan whose frame has no transform";
  EXPECT_TRUE(answered(good(), 5.0)) << "the node stopped after a scan in an unknown frame";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_bad_input");
  return RUN_ALL_TESTS();
}
