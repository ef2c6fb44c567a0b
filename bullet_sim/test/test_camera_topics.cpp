// rostest: the running simulator's panoramic camera - image and camera_info, their size, encoding,
// frame and rate (sim time), and an image that shows the world (many colours, not one).
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <cmath>
#include <set>

TEST(CameraTopics, ImagesAndCameraInfoAtTheConfiguredRate) {
  ros::NodeHandle nh, pnh("~");
  double camera_rate, sim_seconds;
  pnh.param("camera_rate", camera_rate, 5.0);
  pnh.param("sim_seconds", sim_seconds, 10.0);
  ASSERT_TRUE(ros::Time::waitForValid(ros::WallDuration(30.0))) << "no /clock from the simulator";

  int images = 0, infos = 0;
  bool counting = false;
  sensor_msgs::ImageConstPtr last;
  sensor_msgs::CameraInfoConstPtr info;
  auto sub_image = nh.subscribe<sensor_msgs::Image>("camera/image_raw", 50, [&](const sensor_msgs::ImageConstPtr& m) {
    if (!counting) return;
    ++images;
    last = m;
  });
  auto sub_info = nh.subscribe<sensor_msgs::CameraInfo>("camera/camera_info", 50,
                                                        [&](const sensor_msgs::CameraInfoConstPtr& m) {
                                                          if (!counting) return;
                                                          ++infos;
                                                          info = m;
                                                        });
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (sub_image.getNumPublishers() == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  const ros::Time t0 = ros::Time::now();
  counting = true;
  while (ros::ok() && (ros::Time::now() - t0).toSec() < sim_seconds && ros::WallTime::now() < deadline)
    ros::WallDuration(0.01).sleep();
  counting = false;
  spinner.stop();

  const double expected = camera_rate * sim_seconds;
  EXPECT_NEAR(images, expected, 2.0);
  EXPECT_EQ(infos, images);
  ASSERT_TRUE(last && info);
  EXPECT_EQ(last->encoding, "rgb8");
  EXPECT_EQ(last->width, 720u);
  EXPECT_EQ(last->height, 120u);
  EXPECT_EQ(last->step, 720u * 3u);
  EXPECT_EQ(last->data.size(), size_t(720 * 120 * 3));
  EXPECT_EQ(last->header.frame_id, "camera");
  EXPECT_EQ(info->header.stamp, last->header.stamp);
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
