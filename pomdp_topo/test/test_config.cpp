// config/pomdp_topo.yaml documents every parameter with the code's default: check they agree, and
// that the YAML has no key the node does not read.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <string>

#include "pomdp_topo/params_visit.h"

TEST(Config, YamlDefaultsEqualTheCodeDefaults) {
  const YAML::Node root = YAML::LoadFile(CONFIG_FILE);
  pomdp_topo::TopoParams params;
  std::set<std::string> visited;
  pomdp_topo::visitParams(&params, [&](const char* name, auto* value) {
    visited.insert(name);
    const YAML::Node node = root[name];
    ASSERT_TRUE(node.IsDefined() && node.IsScalar()) << name << " is not documented in " << CONFIG_FILE;
    using T = std::remove_pointer_t<decltype(value)>;
    EXPECT_NEAR(static_cast<double>(node.as<T>()), static_cast<double>(*value), 1e-12) << name;
  });
  const std::set<std::string> node_keys = {"map_frame", "odom_frame", "base_frame", "map_file", "load_on_start",
                                           "autosave", "transform_timeout", "markers_period", "realign_updates",
                                           "kidnap_consistency"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    EXPECT_TRUE(visited.count(key) || node_keys.count(key)) << "unknown key " << key;
  }
}

TEST(Config, SharedValuesReachEveryPiece) {
  pomdp_topo::TopoParams p;
  p.pomdp.resolution = 0.25;
  p.pomdp.heading_bins = 8;
  p.pomdp.axis_angle = 0.3;
  p.pomdp.node_radius = 1.5;
  p.sync();
  EXPECT_EQ(p.front_end.resolution, 0.25);
  EXPECT_EQ(p.front_end.heading_bins, 8);
  EXPECT_EQ(p.front_end.axis_angle, 0.3);
  EXPECT_EQ(p.heading.axis_angle, 0.3);
  EXPECT_EQ(p.builder.node_radius, 1.5);
}

// A wrong value ends the node with the parameter's name (pomdp_topo_node throws what this says).
TEST(Config, OutOfRangeValuesAreRefusedWithTheirName) {
  pomdp_topo::TopoParams defaults;
  defaults.sync();
  std::string why;
  EXPECT_TRUE(pomdp_topo::validateParams(defaults, &why)) << why;
  struct Case {
    const char* name;
    void (*spoil)(pomdp_topo::TopoParams*);
  };
  const Case cases[] = {
      {"building/door_max_width", [](pomdp_topo::TopoParams* p) { p->builder.rules.door_max_width = -1.0; }},
      {"loop_new_place_prior", [](pomdp_topo::TopoParams* p) { p->builder.loop_new_place_prior = 0.0; }},
      {"loop_verify_distance", [](pomdp_topo::TopoParams* p) { p->builder.loop_verify_distance = std::nan(""); }},
      {"p_lmap_min_observations", [](pomdp_topo::TopoParams* p) { p->builder.p_lmap_min_observations = 0; }},
      {"opening_tracks/min_sightings", [](pomdp_topo::TopoParams* p) { p->front_end.tracks.min_sightings = 0; }},
      {"opening_tracks/side_angle", [](pomdp_topo::TopoParams* p) { p->front_end.tracks.side_angle = 2.0; }},
      {"max_odometry_step", [](pomdp_topo::TopoParams* p) { p->front_end.max_odometry_step = 0.0; }},
      {"heading_gate_probability", [](pomdp_topo::TopoParams* p) { p->heading.gate_probability = 1.0; }},
      {"heading_initial_variance", [](pomdp_topo::TopoParams* p) { p->heading.initial_variance = -0.1; }},
      {"resolution", [](pomdp_topo::TopoParams* p) { p->pomdp.resolution = 0.0; }},
  };
  for (const Case& c : cases) {
    pomdp_topo::TopoParams p = defaults;
    c.spoil(&p);
    why.clear();
    EXPECT_FALSE(pomdp_topo::validateParams(p, &why)) << c.name;
    EXPECT_NE(why.find(c.name), std::string::npos) << c.name << ": " << why;
  }
}
