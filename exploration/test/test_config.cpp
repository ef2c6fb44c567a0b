// config/exploration.yaml documents every parameter with the code's default: check they agree, and
// that the YAML has no key the node does not read.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <map>
#include <set>

#include "exploration/baseline_params.h"
#include "exploration/params_visit.h"

#include <string>
#include <type_traits>

TEST(Config, YamlDefaultsEqualTheCodeDefaults) {
  const YAML::Node root = YAML::LoadFile(CONFIG_FILE);
  exploration::ExplorationParams params;
  std::set<std::string> visited;
  exploration::visitParams(&params, [&](const char* name, auto* value) {
    visited.insert(name);
    const YAML::Node node = root[name];
    ASSERT_TRUE(node.IsDefined() && node.IsScalar()) << name << " is not documented in " << CONFIG_FILE;
    using T = std::remove_pointer_t<decltype(value)>;
    EXPECT_NEAR(static_cast<double>(node.as<T>()), static_cast<double>(*value), 1e-12) << name;
  });
  const std::set<std::string> node_keys = {"odom_frame", "base_frame", "topo_node", "local_map_node", "control_rate",
                                           "progress_period", "shutdown_when_done", "summary_file", "serve_missions", "mission_client", "freeze_map_for_missions",
                                           "relocation_sigma_xy", "relocation_sigma_theta"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    EXPECT_TRUE(visited.count(key) || node_keys.count(key)) << "unknown key " << key;
  }
}

TEST(Config, BaselineYamlDefaultsEqualTheCodeDefaults) {
  const YAML::Node root = YAML::LoadFile(BASELINE_CONFIG_FILE);
  exploration::BaselineParams params;
  std::set<std::string> visited;
  exploration::visitBaselineParams(&params, [&](const char* name, auto* value) {
    visited.insert(name);
    const YAML::Node node = root[name];
    ASSERT_TRUE(node.IsDefined() && node.IsScalar()) << name << " is not documented in " << BASELINE_CONFIG_FILE;
    using T = std::remove_pointer_t<decltype(value)>;
    if constexpr (std::is_same_v<T, std::string>) {
      EXPECT_EQ(node.as<std::string>(), *value) << name;
    } else {
      EXPECT_NEAR(static_cast<double>(node.as<T>()), static_cast<double>(*value), 1e-12) << name;
    }
  });
  for (const auto& kv : root) EXPECT_TRUE(visited.count(kv.first.as<std::string>())) << "unknown key " << kv.first;
  // The two explorers drive the robot alike.
  exploration::ExplorationParams ours;
  std::map<std::string, double> motion;
  exploration::visitMotionParams(&ours.motion, [&](const char* name, auto* v) { motion[name] = double(*v); });
  exploration::visitMotionParams(&params.motion, [&](const char* name, auto* v) { EXPECT_EQ(motion[name], double(*v)) << name; });
}

TEST(Config, DefaultsAreValid) {
  exploration::ExplorationParams p;
  std::string why;
  EXPECT_TRUE(p.coordinator.valid(&why)) << why;
  EXPECT_TRUE(exploration::MotionController::validate(p.motion, &why)) << why;
  p.coordinator.follow.lookahead = 0.2;
  EXPECT_FALSE(p.coordinator.valid(&why));
}
