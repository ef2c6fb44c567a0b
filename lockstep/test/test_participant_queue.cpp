// rostest: in lockstep, a participant's subscription keeps every message that arrives while the node
// is busy (here: its callback queue not served), even beyond the queue size the node asked for. A
// dropped message would leave a step waiting for its count until the wall-clock timeout.
#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_msgs/String.h>

#include "lockstep/participant.h"

TEST(Participant, AMessageArrivingWhileTheNodeIsBusyIsNotDroppedBeyondTheQueueSize) {
  ros::NodeHandle nh;
  ros::CallbackQueue queue;  // served only below: the node is "busy" until then
  nh.setCallbackQueue(&queue);
  lockstep::Participant participant(nh);
  ASSERT_TRUE(participant.enabled()) << "the test's launch file sets lockstep/enabled";
  int received = 0;
  const uint32_t asked_queue = 1;
  ros::Subscriber sub = participant.subscribe<std_msgs::String>(
      nh, "busy_topic", asked_queue, [&received](const std_msgs::String::ConstPtr&) { ++received; });
  ros::NodeHandle publisher_nh;
  lockstep::Publisher pub = participant.advertise<std_msgs::String>(publisher_nh, "busy_topic", asked_queue);
  for (int i = 0; i < 50 && sub.getNumPublishers() == 0; ++i) ros::WallDuration(0.1).sleep();
  ASSERT_GT(sub.getNumPublishers(), 0u);

  const int sent = 5;
  std_msgs::String m;
  for (int i = 0; i < sent; ++i) pub.publish(m);
  ros::WallDuration(1.0).sleep();  // delivery only: the count checked does not depend on timing
  queue.callAvailable();
  EXPECT_EQ(received, sent);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "participant_queue_test");
  ros::AsyncSpinner spinner(1);  // the global queue (lockstep's step and ack topics)
  spinner.start();
  return RUN_ALL_TESTS();
}
