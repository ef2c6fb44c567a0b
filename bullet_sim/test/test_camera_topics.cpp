// rostest: the running simulator's panoramic camera - image and camera_info, their size, encoding,
// frame and rate (sim time), and an image that shows the world (many colours, not one).
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <cmath>
#include <map>
#include <mutex>
#include <set>

TEST(CameraTopics, ImagesAndCameraInfoAtTheConfiguredRate) {
  ros::NodeHandle nh, pnh("~");
  double camera_rate, sim_seconds;
  pnh.param("camera_rate", camera_rate, 5.0);
  pnh.param("sim_seconds", sim_seconds, 10.0);
  ASSERT_TRUE(ros::Time::waitForValid(ros::WallDuration(30.0))) << "no /clock from the simulator";

  // Frames are counted by their stamps, not by when they arrive: an image and its camera_info are two
  // messages on two connections, so a window of arrival times can cut a frame's pair in two.
  // The image looked at is the last one stamped inside the window, whose camera_info has arrived
  // too (the newest image received may still wait for its own: a race, not a fault).
  std::mutex mutex;
  std::set<ros::Time> image_stamps, info_stamps;
  ros::Time window_end = ros::TIME_MAX;
  sensor_msgs::ImageConstPtr last;
  std::map<ros::Time, sensor_msgs::CameraInfoConstPtr> infos_by_stamp;
  auto sub_image = nh.subscribe<sensor_msgs::Image>("camera/image_raw", 50, [&](const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    image_stamps.insert(m->header.stamp);
    if (m->header.stamp < window_end && (!last || m->header.stamp > last->header.stamp)) last = m;
  });
  auto sub_info = nh.subscribe<sensor_msgs::CameraInfo>("camera/camera_info", 50,
                                                        [&](const sensor_msgs::CameraInfoConstPtr& m) {
                                                          std::lock_guard<std::mutex> lock(mutex);
                                                          info_stamps.insert(m->header.stamp);
                                                          infos_by_stamp[m->header.stamp] = m;
                                                        });
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (sub_image.getNumPublishers() == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  const ros::Time t0 = ros::Time::now() + ros::Duration(1.0);  // connections settled
  const ros::Time t1 = t0 + ros::Duration(sim_seconds);
  {
    std::lock_guard<std::mutex> lock(mutex);
    window_end = t1;
  }
  // Run on past the window so that every frame stamped inside it has arrived on both connections.
  while (ros::ok() && ros::Time::now() < t1 + ros::Duration(2.0) && ros::WallTime::now() < deadline)
    ros::WallDuration(0.01).sleep();
  spinner.stop();

  std::lock_guard<std::mutex> lock(mutex);
  auto in_window = [&](const std::set<ros::Time>& stamps) {
    std::set<ros::Time> inside;
    for (const ros::Time& t : stamps)
      if (t >= t0 && t < t1) inside.insert(t);
    return inside;
  };
  const std::set<ros::Time> images = in_window(image_stamps), infos = in_window(info_stamps);
  const double expected = camera_rate * sim_seconds;
  EXPECT_NEAR(double(images.size()), expected, 1.0);
  EXPECT_EQ(infos, images) << "every image has its camera_info, with the same stamp";
  ASSERT_TRUE(last);
  const auto paired = infos_by_stamp.find(last->header.stamp);
  ASSERT_NE(paired, infos_by_stamp.end()) << "no camera_info with the image's stamp " << last->header.stamp;
  const sensor_msgs::CameraInfoConstPtr info = paired->second;
  EXPECT_EQ(last->encoding, "rgb8");
  EXPECT_EQ(last->width, 720u);
  EXPECT_EQ(last->height, 120u);
  EXPECT_EQ(last->step, 720u * 3u);
  EXPECT_EQ(last->data.size(), size_t(720 * 120 * 3));
  EXPECT_EQ(last->header.frame_id, "camera");
  EXPECT_NEAR(info->K[0], 720.0 / (2.0 * M_PI), 1e-9);  // pixels per radian around
  EXPECT_NEAR(info->K[2], 360.0, 1e-9);
  // The world's walls, floor and ceiling: many colours (noise aside, in coarse bins).
  std::set<int> bins;
  for (size_t i = 0; i + 2 < last->data.size(); i += 3)
    bins.insert((last->data[i] / 32) * 64 + (last->data[i + 1] / 32) * 8 + last->data[i + 2] / 32);
  EXPECT_GE(bins.size(), 5u);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_camera_topics");
  return RUN_ALL_TESTS();
}
