// The building rules live once: config/building.yaml holds every rule with the code's default, and
// no node's own YAML restates one (nor the heading bins and the building's axis, which are
// pomdp_topo's alone); the rules' door test itself.
#include "laser_features/building_rules.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <functional>
#include <set>
#include <string>

namespace {

using laser_features::BuildingRules;

TEST(BuildingRules, TheYamlHoldsEveryRuleWithTheCodesDefault) {
  const YAML::Node root = YAML::LoadFile(std::string(CONFIG_DIR) + "/building.yaml");
  BuildingRules rules;
  std::set<std::string> visited;
  laser_features::visitBuildingRules(&rules, [&](const char* name, double* value) {
    visited.insert(name);
    ASSERT_TRUE(root[name].IsDefined()) << name << " is not in building.yaml";
    EXPECT_DOUBLE_EQ(root[name].as<double>(), *value) << name;
  });
  for (const auto& kv : root) EXPECT_TRUE(visited.count(kv.first.as<std::string>())) << "unknown key " << kv.first;
}

/// Every key (at any depth, "a/b" for nested ones) of a YAML node.
void keys(const YAML::Node& node, const std::string& prefix, std::set<std::string>* out) {
  if (!node.IsMap()) return;
  for (const auto& kv : node) {
    const std::string k = kv.first.as<std::string>();
    out->insert(k);
    keys(kv.second, prefix + k + "/", out);
  }
}

TEST(BuildingRules, NoNodesYamlRestatesThem) {
  std::set<std::string> rules;
  BuildingRules r;
  laser_features::visitBuildingRules(&r, [&](const char* name, double*) { rules.insert(name); });
  rules.insert("min_width");  // the narrowest opening is the narrowest door
  const std::set<std::string> pomdp_topo_only = {"axis_angle", "heading_bins"};
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(CONFIG_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().filename().string();
    if (name == "building.yaml") continue;
    ++files;
    std::set<std::string> found;
    keys(YAML::LoadFile(entry.path().string()), "", &found);
    for (const std::string& k : rules) EXPECT_FALSE(found.count(k)) << name << " restates the building rule " << k;
    if (name != "pomdp_topo.yaml") {
      for (const std::string& k : pomdp_topo_only) EXPECT_FALSE(found.count(k)) << name << " restates pomdp_topo's " << k;
    }
  }
  EXPECT_GE(files, 4);
}

TEST(BuildingRules, DoorsAreTheWidthsBetweenTheNarrowestDoorAndTheWidestAndNoInvertedRange) {
  const BuildingRules rules;
  EXPECT_FALSE(rules.isDoorWidth(0.6));
  EXPECT_TRUE(rules.isDoorWidth(0.7));
  EXPECT_TRUE(rules.isDoorWidth(1.2));
  EXPECT_FALSE(rules.isDoorWidth(1.5));  // the narrowest hallway
  EXPECT_TRUE(rules.doorWide(0.5));
  EXPECT_FALSE(rules.doorWide(1.31));
  EXPECT_TRUE(rules.valid());
  BuildingRules bad;
  bad.door_max_width = 0.5;
  std::string why;
  EXPECT_FALSE(bad.valid(&why));
  EXPECT_NE(why.find("door_max_width"), std::string::npos);
}

}  // namespace
