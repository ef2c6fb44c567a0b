// config/laser_features.yaml documents every parameter with the code's default: check they agree,
// and that the YAML has no key the node does not read.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <set>
#include <sstream>

#include "laser_features/params_visit.h"

namespace {

YAML::Node lookup(const YAML::Node& root, const std::string& path) {
  std::stringstream s(path);
  std::string part;
  YAML::Node node = YAML::Clone(root);
  while (std::getline(s, part, '/')) {
    if (!node.IsMap() || !node[part]) return YAML::Node();
    node = node[part];
  }
  return node;
}

}  // namespace

TEST(Config, YamlDefaultsEqualTheCodeDefaults) {
  const YAML::Node root = YAML::LoadFile(CONFIG_FILE);
  laser_features::FeatureExtractorParams params;
  std::set<std::string> visited;
  laser_features::visitParams(&params, [&](const char* name, auto* value) {
    visited.insert(name);
    const YAML::Node node = lookup(root, name);
    ASSERT_TRUE(node.IsDefined() && node.IsScalar()) << name << " is not documented in " << CONFIG_FILE;
    using T = std::remove_pointer_t<decltype(value)>;
    EXPECT_NEAR(static_cast<double>(node.as<T>()), static_cast<double>(*value), 1e-9) << name;
  });
  // Every key of the YAML is a parameter of the core or one of the node's own.
  const std::set<std::string> node_keys = {"base_frame", "require_transform", "transform_timeout", "odom_frame"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (kv.second.IsMap()) {
      for (const auto& inner : kv.second)
        EXPECT_TRUE(visited.count(key + "/" + inner.first.as<std::string>())) << "unknown key " << key << "/" << inner.first;
    } else {
      EXPECT_TRUE(visited.count(key) || node_keys.count(key)) << "unknown key " << key;
    }
  }
}
