// evaluate_local_map: runs laser_features and one ekf_local_map place on recorded scans and
// odometry (e.g. a CARMEN log converted by scripts/carmen_to_bag) over a bounded stretch, and
// compares the trajectory with the log's reference poses.
//
//   evaluate_local_map --bag B [--first N] [--scans N] [--range-sigma S] [--wheel-noise K]
//                      [--inflation F] [--label NAME] [--plot FILE]
//
// Prints one Markdown row: scans, reference path length, map lines, matched lines per scan, mean NIS (2 when consistent),
// final and mean position error against the reference, for the EKF and for odometry alone. The
// reference (reference_pose) is a SLAM-corrected trajectory, not ground truth.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "ekf_local_map/odometry_noise.h"
#include "ekf_local_map/stochastic_map.h"
#include "laser_features/feature_extractor.h"

namespace lf = laser_features;
namespace ekf = ekf_local_map;

namespace {

lf::Pose2D poseOf(const nav_msgs::Odometry& m) {
  const auto& q = m.pose.pose.orientation;
  return {m.pose.pose.position.x, m.pose.pose.position.y,
          std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))};
}

// The latest pose at or before t.
bool poseAt(const std::map<double, lf::Pose2D>& track, double t, lf::Pose2D* out) {
  auto it = track.upper_bound(t + 1e-6);
  if (it == track.begin()) return false;
  *out = std::prev(it)->second;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string bag_path, label = "log", plot;
  int first = 0, count = 100;
  double range_sigma = 0.02, wheel_noise = 0.01, inflation = 3.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--bag") bag_path = next();
    else if (a == "--first") first = std::atoi(next().c_str());
    else if (a == "--scans") count = std::atoi(next().c_str());
    else if (a == "--range-sigma") range_sigma = std::atof(next().c_str());
    else if (a == "--wheel-noise") wheel_noise = std::atof(next().c_str());
    else if (a == "--inflation") inflation = std::atof(next().c_str());
    else if (a == "--label") label = next();
    else if (a == "--plot") plot = next();
  }
  if (bag_path.empty()) {
    std::fprintf(stderr, "usage: evaluate_local_map --bag B [--first N] [--scans N] [--range-sigma S] "
                         "[--wheel-noise K] [--inflation F] [--label NAME] [--plot FILE]\n");
    return 2;
  }
  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    std::fprintf(stderr, "evaluate_local_map: %s: %s\n", bag_path.c_str(), e.what());
    return 1;
  }
  std::map<double, lf::Pose2D> odom, reference;
  for (const auto& m : rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{"/odom", "/reference_pose"}))) {
    auto o = m.instantiate<nav_msgs::Odometry>();
    if (!o) continue;
    (m.getTopic() == "/odom" ? odom : reference)[o->header.stamp.toSec()] = poseOf(*o);
  }
  if (odom.empty()) {
    std::fprintf(stderr, "evaluate_local_map: %s has no /odom: the filter needs odometry\n", bag_path.c_str());
    return 1;
  }
  lf::FeatureExtractor::Params fp;
  fp.lines.range_sigma = range_sigma;
  lf::FeatureExtractor extractor(fp);
  lf::Features features;
  ekf::StochasticMap map;
  const ekf::OdometryNoise noise = ekf::OdometryNoise::fromWheelModel(wheel_noise, 0.4, inflation);
  ekf::UpdateReport report;
  std::ofstream dump;
  if (!plot.empty()) dump.open(plot);

  int index = -1, used = 0;
  lf::Pose2D last_odom, odom0, ref0;
  double nis_sum = 0, matched_sum = 0, ekf_err_sum = 0, odo_err_sum = 0, ekf_final = 0, odo_final = 0;
  int nis_count = 0, gating_failures = 0;
  double path = 0.0;
  lf::Pose2D last_ref;
  for (const auto& m : rosbag::View(bag, rosbag::TopicQuery("/scan"))) {
    auto scan = m.instantiate<sensor_msgs::LaserScan>();
    if (!scan || ++index < first) continue;
    if (used >= count) break;
    const double t = scan->header.stamp.toSec();
    lf::Pose2D o, ref;
    if (!poseAt(odom, t, &o) || !poseAt(reference, t, &ref)) continue;
    if (used == 0) {
      odom0 = o;
      ref0 = ref;
    } else {
      const lf::Pose2D inc = lf::compose(lf::inverse(last_odom), o);
      map.predict(inc, noise.covariance(inc));
    }
    last_odom = o;
    lf::ScanView v{scan->angle_min, scan->angle_increment, scan->range_min, scan->range_max, scan->ranges.data(),
                   scan->ranges.size()};
    extractor.extract(v, &features);
    map.update(features.lines, lf::Pose2D{}, &report);
    if (report.matched > 0) {
      nis_sum += report.mean_nis;
      ++nis_count;
    }
    matched_sum += report.matched;
    gating_failures += report.gating_failure;
    if (used > 0) path += std::hypot(ref.x - last_ref.x, ref.y - last_ref.y);
    last_ref = ref;
    const lf::Pose2D true_rel = lf::compose(lf::inverse(ref0), ref);
    const lf::Pose2D odo_rel = lf::compose(lf::inverse(odom0), o);
    const lf::Pose2D est = map.robotPose();
    ekf_final = std::hypot(est.x - true_rel.x, est.y - true_rel.y);
    odo_final = std::hypot(odo_rel.x - true_rel.x, odo_rel.y - true_rel.y);
    ekf_err_sum += ekf_final;
    odo_err_sum += odo_final;
    if (dump.is_open())
      dump << "pose " << est.x << " " << est.y << " " << true_rel.x << " " << true_rel.y << " " << odo_rel.x << " "
           << odo_rel.y << "\n";
    ++used;
  }
  if (dump.is_open())
    for (size_t i = 0; i < map.numLines(); ++i) {
      const ekf::MapLine l = map.line(i);
      dump << "line " << l.extent_start.x() << " " << l.extent_start.y() << " " << l.extent_end.x() << " "
           << l.extent_end.y() << "\n";
    }
  if (used == 0) {
    std::fprintf(stderr, "evaluate_local_map: no scan with odometry and a reference pose in that stretch\n");
    return 1;
  }
  std::printf("| %s | %d–%d | %.0f m | %zu | %.1f | %.2f | %d | %.2f m / %.2f m | %.2f m / %.2f m |\n", label.c_str(),
              first, first + used - 1, path, map.numLines(), matched_sum / used, nis_count ? nis_sum / nis_count : NAN,
              gating_failures, ekf_final, ekf_err_sum / used, odo_final, odo_err_sum / used);
  return 0;
}
