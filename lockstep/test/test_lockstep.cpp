// The ROS-free core of lockstep: counts, the simulator's barrier, a participant's input gate.
#include <gtest/gtest.h>

#include "lockstep/input_gate.h"
#include "lockstep/step_barrier.h"

using namespace lockstep;

TEST(Counts, AReceiverHasAStepsInputsOnlyWhenEveryWatchedTopicReachesItsCount) {
  const Counts announced{{"/scan", 3}, {"/features", 2}, {"/markers", 9}};
  std::string why;
  EXPECT_FALSE(covers({{"/scan", 3}, {"/features", 1}}, announced, {"/scan", "/features"}, &why));
  EXPECT_EQ(why, "/features: 1 of 2");
  EXPECT_TRUE(covers({{"/scan", 3}, {"/features", 2}}, announced, {"/scan", "/features"}));  // markers not watched
  EXPECT_TRUE(covers({{"/scan", 4}}, announced, {"/scan"}));
}

TEST(Counts, PublishersOfOneTopicAddUp) {
  EXPECT_EQ(sumCounts({{"/a", 2}}, {{"/a", 3}, {"/b", 1}}), (Counts{{"/a", 5}, {"/b", 1}}));
  EXPECT_EQ(maxCounts({{"/a", 2}}, {{"/a", 1}}), (Counts{{"/a", 2}}));
}

TEST(StepBarrier, TheSimulatorGoesOnOnlyWhenEveryParticipantFinishedTheStep) {
  StepBarrier b({"/laser_features", "/exploration"});
  EXPECT_FALSE(b.allKnown());
  EXPECT_FALSE(b.ack({"/stranger", 100, 0, {}}));
  EXPECT_TRUE(b.ack({"/laser_features", 100, 0, {{"/features", 1}}}));
  EXPECT_FALSE(b.finished(100));
  EXPECT_EQ(b.waitingFor(100), std::vector<std::string>{"/exploration"});
  b.ack({"/exploration", 100, 150, {{"/cmd_vel", 4}}});
  EXPECT_TRUE(b.finished(100));
  EXPECT_FALSE(b.finished(200));
  EXPECT_EQ(b.published({{"/scan", 1}}), (Counts{{"/scan", 1}, {"/features", 1}, {"/cmd_vel", 4}}));
}

TEST(StepBarrier, AnOlderAcknowledgementChangesNothingAndTheNextWakeIsTheEarliestAfterTheStep) {
  StepBarrier b({"/a", "/b"});
  b.ack({"/a", 200, 250, {{"/x", 5}}});
  b.ack({"/a", 100, 120, {{"/x", 3}}});
  EXPECT_TRUE(b.waitingFor(200) == std::vector<std::string>{"/b"});
  EXPECT_EQ(b.published().at("/x"), 5u);
  b.ack({"/b", 200, 0, {}});
  ASSERT_TRUE(b.nextWake(200).has_value());
  EXPECT_EQ(*b.nextWake(200), 250);
  EXPECT_FALSE(b.nextWake(250).has_value());  // nobody asked for a step after 250
}

TEST(StepBarrier, ASilentParticipantExcusedIsNotWaitedForUntilItAcknowledgesAgain) {
  StepBarrier b({"/a", "/b"});
  b.ack({"/a", 100, 0, {}});
  b.ack({"/b", 100, 0, {{"/cmd_vel", 7}}});
  b.excuse(b.waitingFor(200));  // /b died at 100
  b.ack({"/a", 200, 0, {}});
  EXPECT_TRUE(b.finished(200));
  // Restarted, it counts from zero again and is waited for from its next acknowledgement on.
  b.ack({"/b", 300, 0, {{"/cmd_vel", 1}}});
  EXPECT_EQ(b.published().at("/cmd_vel"), 1u);
  EXPECT_EQ(b.waitingFor(400).size(), 2u);
}

namespace {
// Runs every ready step's work, as a participant does; the stamps of the steps finished.
void runReady(InputGate* g, std::vector<Stamp>* steps = nullptr) {
  std::vector<InputGate::Work> work;
  while (const auto s = g->takeReadyStep(&work)) {
    for (auto& w : work) w();
    work.clear();
    if (steps != nullptr) steps->push_back(*s);
  }
}
}  // namespace

TEST(InputGate, GatedWorkRunsAtItsStepOnlyOnceTheUpstreamOutputOfThatStepHasArrived) {
  InputGate g({"/pomdp_topo"});
  g.watch("/features");
  g.watch("/belief");
  std::vector<std::string> log;
  // features(100) arrives; the step is announced; pomdp_topo acknowledges 100 having published one
  // belief, which has not arrived yet (another connection): the step must wait for it.
  g.received("/features");
  g.defer(100, [&] { log.push_back("features@100"); });
  g.step(100, {{"/features", 1}});
  g.ack("/pomdp_topo", 100, {{"/belief", 1}});
  std::vector<Stamp> steps;
  runReady(&g, &steps);
  EXPECT_TRUE(steps.empty());
  EXPECT_EQ(g.waitingFor(), "/belief: 0 of 1");
  g.received("/belief");
  runReady(&g, &steps);
  EXPECT_EQ(steps, std::vector<Stamp>{100});
  EXPECT_EQ(log, std::vector<std::string>{"features@100"});
}

TEST(InputGate, TheSameMessagesInAnyArrivalOrderGiveTheSameWorkInStampOrder) {
  // Two orders of arrival of the same messages: the work runs in the same order.
  auto run = [](bool belief_first) {
    InputGate g({"/pomdp_topo"});
    g.watch("/features");
    g.watch("/belief");
    std::vector<std::string> log;
    auto features = [&](Stamp s) {
      g.received("/features");
      g.defer(s, [&log, s] { log.push_back("f" + std::to_string(s)); });
    };
    g.step(100, {{"/features", 0}});
    if (belief_first) g.received("/belief");
    features(100);
    g.ack("/pomdp_topo", 100, {{"/belief", 1}});
    if (!belief_first) g.received("/belief");
    runReady(&g);
    features(200);
    g.step(200, {{"/features", 2}});
    g.ack("/pomdp_topo", 200, {{"/belief", 1}});
    runReady(&g);
    return log;
  };
  EXPECT_EQ(run(true), run(false));
  EXPECT_EQ(run(true), (std::vector<std::string>{"f100", "f200"}));
}

TEST(InputGate, AStepWaitsForTheAcknowledgementOfEachUpstreamParticipant) {
  InputGate g({"/pomdp_topo", "/ekf_local_map"});
  g.step(100, {});
  g.ack("/pomdp_topo", 100, {});
  g.ack("/laser_features", 100, {});  // not upstream: no matter
  std::vector<Stamp> steps;
  runReady(&g, &steps);
  EXPECT_TRUE(steps.empty());
  EXPECT_EQ(g.waitingFor(), "the acknowledgement of /ekf_local_map");
  g.ack("/ekf_local_map", 100, {});
  runReady(&g, &steps);
  EXPECT_EQ(steps, std::vector<Stamp>{100});
}

TEST(InputGate, ForgivingTakesTheMissingMessagesAsReceived) {
  InputGate g;
  g.watch("/scan");
  g.step(100, {{"/scan", 5}});
  std::vector<Stamp> steps;
  runReady(&g, &steps);
  EXPECT_TRUE(steps.empty());
  g.forgive();
  runReady(&g, &steps);
  EXPECT_EQ(steps, std::vector<Stamp>{100});
  // From there on, counting is exact again.
  g.step(200, {{"/scan", 6}});
  runReady(&g, &steps);
  EXPECT_EQ(steps.size(), 1u);
  g.received("/scan");
  runReady(&g, &steps);
  EXPECT_EQ(steps.size(), 2u);
}

TEST(InputGate, TwoSubscriptionsOfOneTopicWaitUntilBothHaveTheMessage) {
  // A node that maps and steers from the same scans: each scan arrives at both subscriptions.
  InputGate g;
  g.watch("/scan");
  g.watch("/scan");
  g.step(100, {{"/scan", 1}});
  std::vector<Stamp> steps;
  g.received("/scan");  // the first subscription's copy
  runReady(&g, &steps);
  EXPECT_TRUE(steps.empty());
  g.received("/scan");  // the second's
  runReady(&g, &steps);
  EXPECT_EQ(steps, std::vector<Stamp>{100});
}

TEST(InputGate, AnOldOrRepeatedStepIsIgnored) {
  InputGate g;
  g.step(100, {});
  g.step(100, {});
  g.step(50, {});
  std::vector<Stamp> steps;
  runReady(&g, &steps);
  EXPECT_EQ(steps, std::vector<Stamp>{100});
}
