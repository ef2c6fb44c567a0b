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

struct Options {
  std::string bag_path, label = "log", plot;
  int first = 0, count = 100;
  double range_sigma = 0.02, wheel_noise = 0.01, inflation = 3.0;
};

// The command line; false (usage printed) without --bag.
bool parseOptions(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--bag") o->bag_path = next();
    else if (a == "--first") o->first = std::atoi(next().c_str());
    else if (a == "--scans") o->count = std::atoi(next().c_str());
    else if (a == "--range-sigma") o->range_sigma = std::atof(next().c_str());
    else if (a == "--wheel-noise") o->wheel_noise = std::atof(next().c_str());
    else if (a == "--inflation") o->inflation = std::atof(next().c_str());
    else if (a == "--label") o->label = next();
    else if (a == "--plot") o->plot = next();
  }
  if (o->bag_path.empty()) {
    std::fprintf(stderr, "usage: evaluate_local_map --bag B [--first N] [--scans N] [--range-sigma S] "
                         "[--wheel-noise K] [--inflation F] [--label NAME] [--plot FILE]\n");
    return false;
  }
  return true;
}

// The bag's /odom and /reference_pose by stamp.
void readTracks(rosbag::Bag& bag, std::map<double, lf::Pose2D>* odom, std::map<double, lf::Pose2D>* reference) {
  for (const auto& m : rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{"/odom", "/reference_pose"}))) {
    auto o = m.instantiate<nav_msgs::Odometry>();
    if (!o) continue;
    (m.getTopic() == "/odom" ? *odom : *reference)[o->header.stamp.toSec()] = poseOf(*o);
  }
}

// The figures of one stretch: sums over its scans, the last errors.
struct StretchFigures {
  int used = 0, nis_count = 0, gating_failures = 0;
  double nis_sum = 0, matched_sum = 0, ekf_err_sum = 0, odo_err_sum = 0, ekf_final = 0, odo_final = 0, path = 0.0;
};

// One place's EKF over the stretch's scans, each with the odometry and reference pose at its
// stamp; each pose to `dump` if open.
StretchFigures runStretch(rosbag::Bag& bag, const Options& opt, const std::map<double, lf::Pose2D>& odom,
                          const std::map<double, lf::Pose2D>& reference, ekf::StochasticMap* map, std::ofstream* dump) {
  lf::FeatureExtractor::Params fp;
  fp.lines.range_sigma = opt.range_sigma;
  lf::FeatureExtractor extractor(fp);
  lf::Features features;
  const ekf::OdometryNoise noise = ekf::OdometryNoise::fromWheelModel(opt.wheel_noise, 0.4, opt.inflation);
  ekf::UpdateReport report;
  StretchFigures f;
  int index = -1;
  lf::Pose2D last_odom, odom0, ref0, last_ref;
  for (const auto& m : rosbag::View(bag, rosbag::TopicQuery("/scan"))) {
    auto scan = m.instantiate<sensor_msgs::LaserScan>();
    if (!scan || ++index < opt.first) continue;
    if (f.used >= opt.count) break;
    const double t = scan->header.stamp.toSec();
    lf::Pose2D o, ref;
    if (!poseAt(odom, t, &o) || !poseAt(reference, t, &ref)) continue;
    if (f.used == 0) {
      odom0 = o;
      ref0 = ref;
    } else {
      const lf::Pose2D inc = lf::compose(lf::inverse(last_odom), o);
      map->predict(inc, noise.covariance(inc));
    }
    last_odom = o;
    lf::ScanView v{scan->angle_min, scan->angle_increment, scan->range_min, scan->range_max, scan->ranges.data(),
                   scan->ranges.size()};
    extractor.extract(v, &features);
    map->update(features.lines, lf::Pose2D{}, &report);
    if (report.matched > 0) {
      f.nis_sum += report.mean_nis;
      ++f.nis_count;
    }
    f.matched_sum += report.matched;
    f.gating_failures += report.gating_failure;
    if (f.used > 0) f.path += std::hypot(ref.x - last_ref.x, ref.y - last_ref.y);
    last_ref = ref;
    const lf::Pose2D true_rel = lf::compose(lf::inverse(ref0), ref);
    const lf::Pose2D odo_rel = lf::compose(lf::inverse(odom0), o);
    const lf::Pose2D est = map->robotPose();
    f.ekf_final = std::hypot(est.x - true_rel.x, est.y - true_rel.y);
    f.odo_final = std::hypot(odo_rel.x - true_rel.x, odo_rel.y - true_rel.y);
    f.ekf_err_sum += f.ekf_final;
    f.odo_err_sum += f.odo_final;
    if (dump->is_open())
      *dump << "pose " << est.x << " " << est.y << " " << true_rel.x << " " << true_rel.y << " " << odo_rel.x << " "
            << odo_rel.y << "\n";
    ++f.used;
  }
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (!parseOptions(argc, argv, &opt)) return 2;
  rosbag::Bag bag;
  try {
    bag.open(opt.bag_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    std::fprintf(stderr, "evaluate_local_map: %s: %s\n", opt.bag_path.c_str(), e.what());
    return 1;
  }
  std::map<double, lf::Pose2D> odom, reference;
  readTracks(bag, &odom, &reference);
  if (odom.empty()) {
    std::fprintf(stderr, "evaluate_local_map: %s has no /odom: the filter needs odometry\n", opt.bag_path.c_str());
    return 1;
  }
  ekf::StochasticMap map;
  std::ofstream dump;
  if (!opt.plot.empty()) dump.open(opt.plot);
  const StretchFigures f = runStretch(bag, opt, odom, reference, &map, &dump);
  if (dump.is_open())
    for (size_t i = 0; i < map.numLines(); ++i) {
      const ekf::MapLine l = map.line(i);
      dump << "line " << l.extent_start.x() << " " << l.extent_start.y() << " " << l.extent_end.x() << " "
           << l.extent_end.y() << "\n";
    }
  if (f.used == 0) {
    std::fprintf(stderr, "evaluate_local_map: no scan with odometry and a reference pose in that stretch\n");
    return 1;
  }
  std::printf("| %s | %d–%d | %.0f m | %zu | %.1f | %.2f | %d | %.2f m / %.2f m | %.2f m / %.2f m |\n",
              opt.label.c_str(), opt.first, opt.first + f.used - 1, f.path, map.numLines(), f.matched_sum / f.used,
              f.nis_count ? f.nis_sum / f.nis_count : NAN, f.gating_failures, f.ekf_final, f.ekf_err_sum / f.used,
              f.odo_final, f.odo_err_sum / f.used);
  return 0;
}
