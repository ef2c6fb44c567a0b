// config/fingerprint.yaml documents every parameter with the code's default: check they agree, and
// that the YAML has no key the node does not read.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>

#include "fingerprint/params_visit.h"

TEST(Config, YamlDefaultsEqualTheCodeDefaults) {
  const YAML::Node root = YAML::LoadFile(CONFIG_FILE);
  fingerprint::VisualFeatureParams params;
  std::set<std::string> visited;
  fingerprint::visitParams(&params, [&](const char* name, auto* value) {
    visited.insert(name);
    const YAML::Node node = root[name];
    ASSERT_TRUE(node.IsDefined() && node.IsScalar()) << name << " is not documented in " << CONFIG_FILE;
    using T = std::remove_pointer_t<decltype(value)>;
    EXPECT_NEAR(static_cast<double>(node.as<T>()), static_cast<double>(*value), 1e-9) << name;
  });
  const std::set<std::string> node_keys = {"image_timeout", "max_stamp_gap"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    EXPECT_TRUE(visited.count(key) || node_keys.count(key)) << "unknown key " << key;
  }
}

// The camera's noise lives once: config/camera.yaml holds it with the code's default, and no node's
// YAML restates it (the simulator adds it, the fingerprint's edge threshold is derived from it).
TEST(Config, TheCamerasNoiseIsInCameraYamlAloneWithTheCodesDefault) {
  const std::string dir = std::string(CONFIG_FILE).substr(0, std::string(CONFIG_FILE).rfind('/'));
  const YAML::Node camera = YAML::LoadFile(dir + "/camera.yaml");
  ASSERT_TRUE(camera["noise_stddev"]);
  EXPECT_NEAR(camera["noise_stddev"].as<double>(), fingerprint::VisualFeatureParams().image_noise_stddev, 1e-12);
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml" || entry.path().filename() == "camera.yaml") continue;
    ++files;
    const YAML::Node root = YAML::LoadFile(entry.path().string());
    if (!root.IsMap()) continue;
    for (const auto& kv : root) {
      const std::string key = kv.first.as<std::string>();
      EXPECT_TRUE(key != "noise_stddev" && key != "camera_noise_stddev" && key != "image_noise_stddev")
          << entry.path() << " restates the camera's noise as " << key;
    }
  }
  EXPECT_GE(files, 5);
}
