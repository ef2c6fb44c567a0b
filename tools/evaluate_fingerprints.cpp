// evaluate_fingerprints: fingerprint matching alone (Tapus & Siegwart's "most similar node") on a bag
// recorded by `sim.launch camera:=true record:=…`, against the simulator's ground truth.
//
//   evaluate_fingerprints --bag tour.bag [--spacing 1.5] [--near 0.75] [--revisit 60] [--right 1.5]
//
// Along the recorded tour, a fingerprint with an image becomes a reference (a node's) where no
// earlier reference lies within --spacing m (true positions). A later fingerprint whose nearest
// reference lies within --near m and was taken at least --revisit s before (another pass, not the
// same moment) is a test: it is matched against every reference (FingerprintMatcher), and the least
// cost is its answer. Right: the answer is its nearest reference; near: the answer lies within
// --right m of it (a neighbouring reference of the same stretch). Scored with all features and
// with the laser's alone (corners, doors, junctions), side by side. The last line is JSON.
// Evaluation only: with evaluate_features, the one place besides the simulator that reads ground truth.
#include <hybrid_slam_msgs/Fingerprint.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "fingerprint/matcher.h"

namespace {

struct Sample {
  double t = 0.0, x = 0.0, y = 0.0;
  std::vector<fingerprint::Feature> features;
};

std::vector<fingerprint::Feature> fromMessage(const hybrid_slam_msgs::Fingerprint& m) {
  std::vector<fingerprint::Feature> out;
  for (const auto& f : m.features) {
    fingerprint::Feature x;
    x.type = fingerprint::FeatureType(f.type);
    x.bearing = f.bearing;
    x.sigma = f.bearing_sigma;
    x.width = f.angular_width;
    x.hue_bin = f.hue_bin == 255 ? -1 : f.hue_bin;
    x.color = {f.color[0], f.color[1], f.color[2]};
    x.strength = f.strength;
    out.push_back(x);
  }
  return out;
}

std::vector<fingerprint::Feature> laserOnly(const std::vector<fingerprint::Feature>& all) {
  std::vector<fingerprint::Feature> out;
  for (const auto& f : all)
    if (f.type == fingerprint::FeatureType::LaserCorner || f.type == fingerprint::FeatureType::LaserDoor ||
        f.type == fingerprint::FeatureType::LaserJunction)
      out.push_back(f);
  return out;
}

struct Score {
  int tests = 0, right = 0, near = 0;
};

struct Options {
  std::string bag_path;
  double spacing = 1.5, near = 0.75, revisit = 60.0, right_radius = 1.5;
};

// The command line; false (the error printed) on an unknown option or without --bag.
bool parseOptions(int argc, char** argv, Options* o) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--bag") o->bag_path = argv[i + 1];
    else if (k == "--spacing") o->spacing = std::atof(argv[i + 1]);
    else if (k == "--near") o->near = std::atof(argv[i + 1]);
    else if (k == "--revisit") o->revisit = std::atof(argv[i + 1]);
    else if (k == "--right") o->right_radius = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "evaluate_fingerprints: unknown option %s\n", k.c_str());
      return false;
    }
  }
  if (o->bag_path.empty()) {
    std::fprintf(stderr, "usage: evaluate_fingerprints --bag B [--spacing M] [--near M] [--revisit S] [--right M]\n");
    return false;
  }
  return true;
}

// The bag's fingerprints with an image, each with the true position at its stamp; false (the error
// printed) if the bag cannot be read.
bool readSamples(const std::string& bag_path, std::vector<Sample>* samples) {
  std::map<double, std::pair<double, double>> truth;  // t -> (x, y)
  std::vector<std::pair<double, hybrid_slam_msgs::Fingerprint::ConstPtr>> prints;
  try {
    rosbag::Bag bag(bag_path);
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/ground_truth", "/fingerprint"}));
    for (const rosbag::MessageInstance& m : view) {
      if (auto o = m.instantiate<nav_msgs::Odometry>())
        truth[o->header.stamp.toSec()] = {o->pose.pose.position.x, o->pose.pose.position.y};
      else if (auto f = m.instantiate<hybrid_slam_msgs::Fingerprint>())
        if (f->has_image) prints.emplace_back(f->header.stamp.toSec(), f);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate_fingerprints: %s: %s\n", bag_path.c_str(), e.what());
    return false;
  }
  for (const auto& [t, f] : prints) {
    auto it = truth.lower_bound(t - 1e-6);
    if (it == truth.end() || std::abs(it->first - t) > 0.05) continue;  // no true pose at its stamp
    samples->push_back(Sample{t, it->second.first, it->second.second, fromMessage(*f)});
  }
  return true;
}

// References along the tour (`refs`), and the tests: later passes near a reference (sample, its
// nearest reference).
void referencesAndTests(const std::vector<Sample>& samples, const Options& opt, std::vector<size_t>* refs,
                        std::vector<std::pair<size_t, size_t>>* tests) {
  for (size_t i = 0; i < samples.size(); ++i) {
    double best = 1e18;
    size_t nearest = 0;
    for (size_t r : *refs) {
      const double d = std::hypot(samples[r].x - samples[i].x, samples[r].y - samples[i].y);
      if (d < best) best = d, nearest = r;
    }
    if (refs->empty() || best > opt.spacing) refs->push_back(i);
    else if (best <= opt.near && samples[i].t - samples[nearest].t >= opt.revisit) tests->emplace_back(i, nearest);
  }
}

void printReport(size_t samples, size_t refs, size_t tests, double features_sum, double laser_sum, const Score& all,
                 const Score& laser, double right_radius) {
  auto pct = [](int a, int n) { return n ? 100.0 * a / n : 0.0; };
  std::printf("evaluate_fingerprints: %zu fingerprints with an image, %zu references (%.1f features each, %.1f the laser's), %zu tests\n",
              samples, refs, features_sum / refs, laser_sum / refs, tests);
  std::printf("  camera + laser: %d of %d right (%.1f %%), %d within %.1f m (%.1f %%)\n", all.right, all.tests,
              pct(all.right, all.tests), all.near, right_radius, pct(all.near, all.tests));
  std::printf("  laser alone:    %d of %d right (%.1f %%), %d within %.1f m (%.1f %%)\n", laser.right, laser.tests,
              pct(laser.right, laser.tests), laser.near, right_radius, pct(laser.near, laser.tests));
  std::printf("{\"fingerprints\": %zu, \"references\": %zu, \"tests\": %d, \"right\": %d, \"near\": %d, "
              "\"laser_right\": %d, \"laser_near\": %d, \"right_pct\": %.1f, \"laser_right_pct\": %.1f}\n",
              samples, refs, all.tests, all.right, all.near, laser.right, laser.near, pct(all.right, all.tests),
              pct(laser.right, laser.tests));
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (!parseOptions(argc, argv, &opt)) return 2;
  std::vector<Sample> samples;
  if (!readSamples(opt.bag_path, &samples)) return 1;
  if (samples.empty()) {
    std::fprintf(stderr, "evaluate_fingerprints: %s: no fingerprint with an image and a true pose (camera:=true?)\n",
                 opt.bag_path.c_str());
    return 1;
  }
  std::vector<size_t> refs;
  std::vector<std::pair<size_t, size_t>> tests;
  referencesAndTests(samples, opt, &refs, &tests);
  const fingerprint::FingerprintMatcher matcher;
  Score all, laser;
  double features_sum = 0.0, laser_sum = 0.0;
  for (size_t r : refs) features_sum += samples[r].features.size();
  std::map<size_t, std::vector<fingerprint::Feature>> laser_refs;  // each reference's laser features, once
  for (size_t r : refs) {
    laser_refs[r] = laserOnly(samples[r].features);
    laser_sum += laser_refs[r].size();
  }
  for (const auto& [i, nearest] : tests) {
    for (int mode = 0; mode < 2; ++mode) {
      const auto seen = mode == 0 ? samples[i].features : laserOnly(samples[i].features);
      double best_cost = 1e18;
      size_t answer = refs.front();
      for (size_t r : refs) {
        const double c = matcher.match(seen, mode == 0 ? samples[r].features : laser_refs[r]).cost;
        if (c < best_cost) best_cost = c, answer = r;
      }
      Score& s = mode == 0 ? all : laser;
      ++s.tests;
      s.right += answer == nearest;
      s.near += std::hypot(samples[answer].x - samples[i].x, samples[answer].y - samples[i].y) <= opt.right_radius;
    }
  }
  printReport(samples.size(), refs.size(), tests.size(), features_sum, laser_sum, all, laser, opt.right_radius);
  return 0;
}
