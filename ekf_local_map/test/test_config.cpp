// config/ekf_local_map.yaml documents every filter parameter with the code's default: check they
// agree (and the save option's), and that the YAML has no key the node does not read.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <set>

#include "ekf_local_map/params_visit.h"
#include "ekf_local_map/persistence.h"

TEST(Config, YamlDefaultsEqualTheCodeDefaults) {
  const YAML::Node root = YAML::LoadFile(CONFIG_FILE);
  ekf_local_map::StochasticMapParams params;
  std::set<std::string> visited;
  ekf_local_map::visitParams(&params, [&](const char* name, auto* value) {
    visited.insert(name);
    const YAML::Node node = root[name];
    ASSERT_TRUE(node.IsDefined() && node.IsScalar()) << name << " is not documented in " << CONFIG_FILE;
    using T = std::remove_pointer_t<decltype(value)>;
    EXPECT_NEAR(static_cast<double>(node.as<T>()), static_cast<double>(*value), 1e-12) << name;
  });
  // The node's own keys (frames, odometry noise, files); everything else must be a filter parameter.
  const std::set<std::string> node_keys = {"map_frame", "odom_frame", "base_frame", "place_frame_prefix", "publish_tf",
                                           "transform_tolerance", "transform_timeout", "map_file", "load_on_start",
                                           "store_joint_covariance", "odom_wheel_noise", "odom_wheel_base",
                                           "odom_inflation"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    EXPECT_TRUE(visited.count(key) || node_keys.count(key)) << "unknown key " << key;
  }
  // The node's odometry defaults are the noise model's.
  EXPECT_DOUBLE_EQ(root["odom_wheel_noise"].as<double>(), 0.005);
  EXPECT_DOUBLE_EQ(root["odom_wheel_base"].as<double>(), 0.40);
  EXPECT_DOUBLE_EQ(root["odom_inflation"].as<double>(), 1.2);
  // The save option's default is the core's.
  ASSERT_TRUE(root["store_joint_covariance"].IsDefined());
  EXPECT_EQ(root["store_joint_covariance"].as<bool>(), ekf_local_map::PlacesSaveOptions().store_joint_covariance);
}
