// rostest: counts what the running simulator publishes over a span of sim time.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>

namespace {

struct Counts {
  int scans = 0, odom = 0, tf = 0, clock = 0, truth = 0;
  size_t beams = 0;
  bool scan_frame_ok = true, odom_frames_ok = true;
};

}  // namespace

TEST(SimRates, PublishesAtTheConfiguredRates) {
  ros::NodeHandle nh, pnh("~");
  double scan_rate, odom_rate, clock_rate, sim_seconds;
  pnh.param("scan_rate", scan_rate, 10.0);
  pnh.param("odom_rate", odom_rate, 50.0);
  pnh.param("clock_rate", clock_rate, 100.0);
  pnh.param("sim_seconds", sim_seconds, 20.0);

  // Wait for the clock to run before counting.
  ASSERT_TRUE(ros::Time::waitForValid(ros::WallDuration(30.0))) << "no /clock from the simulator";
  Counts c;
  bool counting = false;
  auto sub_scan = nh.subscribe<sensor_msgs::LaserScan>("scan", 100, [&](const sensor_msgs::LaserScanConstPtr& m) {
    if (!counting) return;
    ++c.scans;
    c.beams = m->ranges.size();
    c.scan_frame_ok &= m->header.frame_id == "laser";
  });
  auto sub_odom = nh.subscribe<nav_msgs::Odometry>("odom", 500, [&](const nav_msgs::OdometryConstPtr& m) {
    if (!counting) return;
    ++c.odom;
    c.odom_frames_ok &= m->header.frame_id == "odom" && m->child_frame_id == "base_link";
  });
  auto sub_truth = nh.subscribe<nav_msgs::Odometry>("ground_truth", 500, [&](const nav_msgs::OdometryConstPtr&) {
    if (counting) ++c.truth;
  });
  auto sub_tf = nh.subscribe<tf2_msgs::TFMessage>("/tf", 500, [&](const tf2_msgs::TFMessageConstPtr& m) {
    if (!counting) return;
    for (const auto& t : m->transforms)
      if (t.header.frame_id == "odom" && t.child_frame_id == "base_link") ++c.tf;
  });
  auto sub_clock = nh.subscribe<rosgraph_msgs::Clock>("/clock", 1000, [&](const rosgraph_msgs::ClockConstPtr&) {
    if (counting) ++c.clock;
  });
  bool markers = false;
  auto sub_markers = nh.subscribe<visualization_msgs::MarkerArray>(
      "world_markers", 1, [&](const visualization_msgs::MarkerArrayConstPtr& m) { markers = !m->markers.empty(); });

  ros::AsyncSpinner spinner(1);
  spinner.start();
  ros::Duration(1.0).sleep();  // let the subscriptions connect (sim time)
  counting = true;
  const ros::Time start = ros::Time::now();
  ros::Duration(sim_seconds).sleep();
  counting = false;
  const double span = (ros::Time::now() - start).toSec();
  spinner.stop();

  EXPECT_NEAR(c.scans / span, scan_rate, 0.1 * scan_rate);
  EXPECT_NEAR(c.odom / span, odom_rate, 0.1 * odom_rate);
  EXPECT_NEAR(c.truth / span, odom_rate, 0.1 * odom_rate);
  EXPECT_NEAR(c.tf / span, odom_rate, 0.1 * odom_rate);
  EXPECT_NEAR(c.clock / span, clock_rate, 0.1 * clock_rate);
  EXPECT_EQ(c.beams, 720u);
  EXPECT_TRUE(c.scan_frame_ok);
  EXPECT_TRUE(c.odom_frames_ok);
  EXPECT_TRUE(markers) << "no latched world_markers";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_sim_rates");
  return RUN_ALL_TESTS();
}
