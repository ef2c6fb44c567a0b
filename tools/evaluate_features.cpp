// evaluate_features: scores laser features against the simulator's ground truth.
//
//   evaluate_features --bag tour.bag --world worlds/institute.yaml [--stride N] [--max-scans N]
//                     [--lines FILE] [--dump-scans FILE] [--label NAME] [--config YAML]
//   evaluate_features --bag real.bag [--scan-topic T] [--plot FILE] [--plot-scans N] [--label NAME]
//
// Reads the scans and the ground truth of a bag recorded by `sim.launch record:=…`, runs the
// laser_features extractor (default parameters, or those of --config, e.g. config/laser_features.yaml) on every N-th scan and compares with the world:
// lines against the box faces the scan really hit, corners against the corners of those faces,
// openings against the world's doors, the place type against the regions. `--lines FILE` scores
// lines produced by another extractor instead (one line per segment: "scan alpha r c00 c01 c10 c11
// sx sy ex ey", scan = index among the evaluated scans); `--dump-scans FILE` writes the evaluated
// scans as text ("angle_min increment range_min range_max n r0 … r(n-1)") for such an extractor.
// Without --world it reports features per scan and the time on any bag (real data) and can dump a
// few scans with their features for scripts/plot_features.py.
// Evaluation only: this is the one place besides the simulator that reads ground truth.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_sim/ray_caster.h"
#include "bullet_sim/world.h"
#include "laser_features/feature_extractor.h"
#include "laser_features/params_visit.h"

#include <yaml-cpp/yaml.h>

namespace lf = laser_features;
namespace bs = bullet_sim;

namespace {

struct Options {
  std::string bag, world, lines_file, dump_file, config, label = "hybrid_slam";
  std::string scan_topic = "/scan", plot_file;
  int plot_scans = 6;
  int stride = 1;
  int max_scans = 0;
};

// A true line: a box face, in the laser frame, with the part of it the scan hit.
struct TrueLine {
  lf::Line line;
  Eigen::Vector2d a, b;  // visible extent end points (laser frame)
  int beams = 0;
};

struct Stats {
  std::vector<double> d_alpha, d_r, d_mid, nees;
  std::vector<double> micros;  // extraction time per scan
  int expected_lines = 0, found_lines = 0, extracted_lines = 0, false_lines = 0;
  int expected_corners = 0, found_corners = 0, extracted_corners = 0, false_corners = 0;
  int visible_doors = 0, found_doors = 0, extracted_openings = 0, false_openings = 0;
  int place_total = 0, place_right = 0, place_unknown = 0;
  int hallway_scans = 0, hallway_right = 0, room_scans = 0, room_right = 0;
  int typed_openings = 0, false_typed_openings = 0;  // DOOR or JUNCTION only
  int scans = 0;
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}

lf::Pose2D yawPose(const nav_msgs::Odometry& m) {
  const auto& q = m.pose.pose.orientation;
  return {m.pose.pose.position.x, m.pose.pose.position.y,
          std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))};
}

// Faces hit by the exact scan from `laser` (world pose), grouped per face, in the laser frame.
std::vector<TrueLine> visibleFaces(const bs::RayCaster2D& caster, const lf::Pose2D& laser,
                                   const sensor_msgs::LaserScan& scan, int min_beams, double min_length) {
  std::map<size_t, std::vector<Eigen::Vector2d>> hits;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double a = laser.theta + scan.angle_min + i * scan.angle_increment;
    size_t face = 0;
    const double d = caster.cast(laser.x, laser.y, std::cos(a), std::sin(a), scan.range_max, &face);
    if (!std::isfinite(d) || caster.primitive(face).radius > 0) continue;
    const double b = scan.angle_min + i * scan.angle_increment;
    hits[face].push_back(Eigen::Vector2d(d * std::cos(b), d * std::sin(b)));
  }
  std::vector<TrueLine> out;
  const lf::Pose2D world_to_laser = lf::inverse(laser);
  for (const auto& [face, points] : hits) {
    if (static_cast<int>(points.size()) < min_beams) continue;
    const auto& p = caster.primitive(face);
    const Eigen::Vector2d a = lf::transformPoint(world_to_laser, {p.ax, p.ay});
    const Eigen::Vector2d b = lf::transformPoint(world_to_laser, {p.bx, p.by});
    TrueLine t;
    t.line = lf::lineThroughPoints(a, b);
    // Visible extent: the hit points' projections along the line.
    const Eigen::Vector2d dir = t.line.direction();
    double lo = 1e9, hi = -1e9;
    for (const auto& q : points) {
      lo = std::min(lo, dir.dot(q));
      hi = std::max(hi, dir.dot(q));
    }
    if (hi - lo < min_length) continue;
    const Eigen::Vector2d foot = t.line.r * t.line.normal();
    t.a = foot + lo * dir;
    t.b = foot + hi * dir;
    t.beams = static_cast<int>(points.size());
    out.push_back(t);
  }
  return out;
}

// Overlap length of segment (p, q) with the extent (a, b) along `line`.
double overlap(const lf::Line& line, const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& a,
               const Eigen::Vector2d& b) {
  const Eigen::Vector2d dir = line.direction();
  const double p0 = std::min(dir.dot(p), dir.dot(q)), p1 = std::max(dir.dot(p), dir.dot(q));
  const double a0 = std::min(dir.dot(a), dir.dot(b)), a1 = std::max(dir.dot(a), dir.dot(b));
  return std::max(0.0, std::min(p1, a1) - std::max(p0, a0));
}

struct Segment {
  lf::Line line;
  Eigen::Vector2d start, end;
};

// Matches extracted segments to true faces: same line within 5° and 10 cm, overlapping the face's
// visible part for at least half the segment's length; the closest such face.
void scoreLines(const std::vector<Segment>& extracted, const std::vector<TrueLine>& truth, Stats* s) {
  std::vector<bool> face_found(truth.size(), false);
  s->expected_lines += static_cast<int>(truth.size());
  s->extracted_lines += static_cast<int>(extracted.size());
  for (const Segment& e : extracted) {
    int best = -1;
    double best_cost = 1e9;
    Eigen::Vector2d best_diff;
    for (size_t k = 0; k < truth.size(); ++k) {
      const Eigen::Vector2d d = lf::lineDifference(e.line, truth[k].line);
      if (std::abs(d[0]) > 5.0 * M_PI / 180 || std::abs(d[1]) > 0.10) continue;
      const double length = (e.end - e.start).norm();
      if (overlap(truth[k].line, e.start, e.end, truth[k].a, truth[k].b) < 0.5 * length) continue;
      const double cost = std::abs(d[0]) + std::abs(d[1]);
      if (cost < best_cost) {
        best_cost = cost;
        best = static_cast<int>(k);
        best_diff = d;
      }
    }
    if (best < 0) {
      ++s->false_lines;
      continue;
    }
    face_found[best] = true;
    s->d_alpha.push_back(std::abs(best_diff[0]));
    s->d_r.push_back(std::abs(best_diff[1]));
    s->d_mid.push_back(std::abs(lf::signedDistanceToLine(truth[best].line, 0.5 * (e.start + e.end))));
    const Eigen::Matrix2d c = e.line.cov;
    if (c.determinant() > 0) s->nees.push_back(best_diff.dot(c.inverse() * best_diff));
  }
  for (bool f : face_found) s->found_lines += f;
}

// True corners: two visible faces meeting at an end of both visible extents (within 10 cm) at more
// than 30°. An extracted corner within 15 cm of one is found.
void scoreCorners(const std::vector<lf::Corner>& extracted, const std::vector<TrueLine>& truth, Stats* s) {
  std::vector<Eigen::Vector2d> corners;
  for (size_t i = 0; i < truth.size(); ++i)
    for (size_t j = i + 1; j < truth.size(); ++j) {
      if (lf::angleBetweenLines(truth[i].line, truth[j].line) < M_PI / 6) continue;
      Eigen::Vector2d p;
      if (!lf::intersectLines(truth[i].line, truth[j].line, &p)) continue;
      auto near_end = [&](const TrueLine& t) { return std::min((p - t.a).norm(), (p - t.b).norm()) < 0.10; };
      if (near_end(truth[i]) && near_end(truth[j])) corners.push_back(p);
    }
  s->expected_corners += static_cast<int>(corners.size());
  s->extracted_corners += static_cast<int>(extracted.size());
  std::vector<bool> found(corners.size(), false);
  for (const lf::Corner& c : extracted) {
    bool matched = false;
    for (size_t k = 0; k < corners.size(); ++k)
      if ((c.position - corners[k]).norm() < 0.15) {
        found[k] = true;
        matched = true;
      }
    if (!matched) ++s->false_corners;
  }
  for (bool f : found) s->found_corners += f;
}

// A door is visible when its centre and both jambs are in line of sight within 6 m. An extracted
// opening whose centre lies within 0.4 m of a door (any door) is right; one of a visible door finds it.
void scoreOpenings(const std::vector<lf::Opening>& extracted, const bs::World& world, const bs::RayCaster2D& caster,
                   const lf::Pose2D& laser, Stats* s) {
  std::vector<int> visible;
  for (size_t k = 0; k < world.doors.size(); ++k) {
    const bs::Door& d = world.doors[k];
    const double along_x = caster.cast(d.center.x, d.center.y, 1, 0, 50) + caster.cast(d.center.x, d.center.y, -1, 0, 50);
    const double along_y = caster.cast(d.center.x, d.center.y, 0, 1, 50) + caster.cast(d.center.x, d.center.y, 0, -1, 50);
    const Eigen::Vector2d wall_dir = along_x <= along_y ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(0, 1);
    const Eigen::Vector2d c(d.center.x, d.center.y);
    bool seen = true;
    for (double side : {-0.45, 0.0, 0.45}) {  // jambs, slightly inside the opening, and the centre
      const Eigen::Vector2d target = c + side * d.width * wall_dir;
      const Eigen::Vector2d ray = target - laser.translation();
      const double dist = ray.norm();
      if (dist > 6.0 || dist < 0.3) {
        seen = false;
        break;
      }
      if (caster.cast(laser.x, laser.y, ray.x() / dist, ray.y() / dist, dist) < dist - 0.05) seen = false;
    }
    // Seen edge-on (the robot in the wall's line) it shows no gap.
    const Eigen::Vector2d normal(-wall_dir.y(), wall_dir.x());
    if (std::abs(normal.dot((c - laser.translation()).normalized())) < 0.2) seen = false;
    if (seen) visible.push_back(static_cast<int>(k));
  }
  s->visible_doors += static_cast<int>(visible.size());
  s->extracted_openings += static_cast<int>(extracted.size());
  std::vector<bool> found(visible.size(), false);
  for (const lf::Opening& o : extracted) {
    const Eigen::Vector2d w = lf::transformPoint(laser, o.center);
    bool near_any = false;
    for (const bs::Door& d : world.doors) near_any |= (w - Eigen::Vector2d(d.center.x, d.center.y)).norm() < 0.4;
    if (!near_any) ++s->false_openings;
    if (o.kind != lf::OpeningKind::kUnknown) {
      ++s->typed_openings;
      if (!near_any) ++s->false_typed_openings;
    }
    for (size_t k = 0; k < visible.size(); ++k) {
      const bs::Door& d = world.doors[visible[k]];
      if ((w - Eigen::Vector2d(d.center.x, d.center.y)).norm() < 0.4) found[k] = true;
    }
  }
  for (bool f : found) s->found_doors += f;
}

size_t scan_beams_of(rosbag::Bag& bag, const std::string& topic) {
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic)))
    if (auto s = m.instantiate<sensor_msgs::LaserScan>()) return s->ranges.size();
  return 0;
}

// Without a world: features per scan and time on any bag (real data), and a dump of a few scans
// with their features for scripts/plot_features.py.
int reportRealData(const Options& opt, const lf::FeatureExtractor::Params& params, rosbag::Bag* bag) {
  rosbag::View view(*bag, rosbag::TopicQuery(opt.scan_topic));
  if (view.size() == 0) {
    std::string topics;
    for (const rosbag::ConnectionInfo* c : rosbag::View(*bag).getConnections()) topics += " " + c->topic;
    std::fprintf(stderr, "evaluate_features: %s has no messages on %s; its topics:%s\n", opt.bag.c_str(),
                 opt.scan_topic.c_str(), topics.c_str());
    return 1;
  }
  const size_t total = view.size();
  const size_t plot_every = std::max<size_t>(1, total / opt.plot_scans);
  std::ofstream plot;
  if (!opt.plot_file.empty()) plot.open(opt.plot_file);
  lf::FeatureExtractor extractor(params);
  lf::Features features;
  std::vector<double> micros, lines, corners, openings;
  int errors = 0, hallway = 0, room = 0;
  size_t index = 0;
  for (const rosbag::MessageInstance& m : view) {
    auto scan = m.instantiate<sensor_msgs::LaserScan>();
    if (!scan) continue;
    lf::ScanView v{scan->angle_min, scan->angle_increment, scan->range_min, scan->range_max, scan->ranges.data(),
                   scan->ranges.size()};
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = extractor.extract(v, &features);
    micros.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    errors += !ok;
    lines.push_back(features.lines.size());
    corners.push_back(features.corners.size());
    openings.push_back(features.openings.size());
    hallway += features.place_type == lf::PlaceType::kHallway;
    room += features.place_type == lf::PlaceType::kRoom;
    if (plot.is_open() && index % plot_every == plot_every / 2) {
      plot << "scan " << index << " " << scan->header.stamp.toSec() << "\n";
      plot << "points";
      for (size_t i = 0; i < scan->ranges.size(); ++i) {
        const float r = scan->ranges[i];
        if (!std::isfinite(r) || r < scan->range_min || r > scan->range_max) continue;
        const double a = scan->angle_min + i * scan->angle_increment;
        plot << " " << r * std::cos(a) << " " << r * std::sin(a);
      }
      plot << "\n";
      for (const auto& l : features.lines)
        plot << "line " << l.start.x() << " " << l.start.y() << " " << l.end.x() << " " << l.end.y() << "\n";
      for (const auto& c : features.corners)
        plot << "corner " << c.position.x() << " " << c.position.y() << " " << c.theta << " " << c.convex << "\n";
      for (const auto& o : features.openings)
        plot << "opening " << o.left.x() << " " << o.left.y() << " " << o.right.x() << " " << o.right.y() << " "
             << static_cast<int>(o.kind) << "\n";
      plot << "place " << static_cast<int>(features.place_type) << " " << features.place_confidence << "\n";
    }
    ++index;
  }
  std::printf("| %s | %zu | %zu | %.1f | %.1f | %.1f | %.0f%% / %.0f%% | %.1f µs | %d |\n", opt.label.c_str(), index,
              scan_beams_of(*bag, opt.scan_topic), mean(lines), mean(corners), mean(openings), 100.0 * hallway / index,
              100.0 * room / index, percentile(micros, 0.5), errors);
  return 0;
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--bag") o->bag = next();
    else if (a == "--world") o->world = next();
    else if (a == "--lines") o->lines_file = next();
    else if (a == "--dump-scans") o->dump_file = next();
    else if (a == "--label") o->label = next();
    else if (a == "--config") o->config = next();
    else if (a == "--scan-topic") o->scan_topic = next();
    else if (a == "--plot") o->plot_file = next();
    else if (a == "--plot-scans") o->plot_scans = std::max(1, std::atoi(next().c_str()));
    else if (a == "--stride") o->stride = std::max(1, std::atoi(next().c_str()));
    else if (a == "--max-scans") o->max_scans = std::atoi(next().c_str());
    else return false;
  }
  return !o->bag.empty();
}

void usage() {
  std::fprintf(stderr,
               "usage: evaluate_features --bag BAG [--world WORLD.yaml] [--stride N] [--max-scans N] [--lines FILE]\n"
               "       [--dump-scans FILE] [--label NAME] [--config YAML] [--scan-topic T] [--plot FILE] [--plot-scans N]\n"
               "  with --world: scores against the simulator's ground truth (bag from sim.launch record:=...)\n"
               "  without: features per scan and time on any bag, one Markdown table row\n");
}

// A scan as a line of text: angle_min, angle_increment, range_min, range_max, count, the ranges.
void dumpScan(const sensor_msgs::LaserScan& scan, std::ofstream* dump) {
  *dump << scan.angle_min << " " << scan.angle_increment << " " << scan.range_min << " " << scan.range_max << " "
        << scan.ranges.size();
  for (float r : scan.ranges) *dump << " " << r;
  *dump << "\n";
}

// The node's YAML (config/laser_features.yaml format): every parameter it names.
bool loadParams(const std::string& config, lf::FeatureExtractor::Params* params) {
  try {
    const YAML::Node root = YAML::LoadFile(config);
    lf::visitParams(params, [&](const char* name, auto* value) {
      YAML::Node node = YAML::Clone(root);
      std::stringstream path(name);
      std::string part;
      while (std::getline(path, part, '/') && node.IsMap()) node = node[part];
      if (node.IsDefined() && node.IsScalar()) *value = node.as<std::remove_pointer_t<decltype(value)>>();
    });
  } catch (const YAML::Exception& e) {
    std::fprintf(stderr, "evaluate_features: %s: %s\n", config.c_str(), e.what());
    return false;
  }
  return true;
}

// Lines extracted by another tool, a line each: scan index, alpha, r, covariance (4), start, end.
bool readExternalLines(const std::string& file, std::map<int, std::vector<Segment>>* external) {
  std::ifstream in(file);
  if (!in) {
    std::fprintf(stderr, "evaluate_features: cannot read %s\n", file.c_str());
    return false;
  }
  int idx;
  Segment s;
  while (in >> idx >> s.line.alpha >> s.line.r >> s.line.cov(0, 0) >> s.line.cov(0, 1) >> s.line.cov(1, 0) >>
         s.line.cov(1, 1) >> s.start.x() >> s.start.y() >> s.end.x() >> s.end.y())
    (*external)[idx].push_back(s);
  return true;
}

std::vector<std::pair<double, lf::Pose2D>> truthTrack(rosbag::Bag* bag) {
  std::vector<std::pair<double, lf::Pose2D>> track;
  for (const rosbag::MessageInstance& m : rosbag::View(*bag, rosbag::TopicQuery("/ground_truth")))
    if (auto t = m.instantiate<nav_msgs::Odometry>()) track.emplace_back(t->header.stamp.toSec(), yawPose(*t));
  return track;
}

// The scan's place type against the region the laser is in (scans outside every region not counted).
void scorePlaceType(lf::PlaceType type, const bs::World& world, const lf::Pose2D& laser, Stats* s) {
  const int region = world.regionAt({laser.x, laser.y});
  if (region < 0) return;
  ++s->place_total;
  const bool hallway = world.regions[region].hallway;
  const bool right = type != lf::PlaceType::kUnknown && (type == lf::PlaceType::kHallway) == hallway;
  if (type == lf::PlaceType::kUnknown) ++s->place_unknown;
  s->place_right += right;
  (hallway ? s->hallway_scans : s->room_scans)++;
  (hallway ? s->hallway_right : s->room_right) += right;
}

void printReport(const Options& opt, const Stats& s) {
  const double deg = 180.0 / M_PI;
  std::printf("## %s on %s (%d scans)\n\n", opt.label.c_str(), opt.bag.c_str(), s.scans);
  std::printf("| lines | |\n|---|---|\n");
  std::printf("| mean / p95 |dα| | %.3f° / %.3f° |\n", mean(s.d_alpha) * deg, percentile(s.d_alpha, 0.95) * deg);
  std::printf("| mean / p95 |dr| | %.1f mm / %.1f mm |\n", mean(s.d_r) * 1e3, percentile(s.d_r, 0.95) * 1e3);
  std::printf("| mean / p95 distance of the segment's midpoint from the wall | %.1f mm / %.1f mm |\n",
              mean(s.d_mid) * 1e3, percentile(s.d_mid, 0.95) * 1e3);
  std::printf("| mean NEES (2 dof: ~2) | %.2f (median %.2f) |\n", mean(s.nees), percentile(s.nees, 0.5));
  std::printf("| recall (faces ≥ 6 beams, ≥ 0.2 m) | %.1f%% (%d / %d) |\n", 100.0 * s.found_lines / std::max(1, s.expected_lines),
              s.found_lines, s.expected_lines);
  std::printf("| false lines | %.1f%% (%d / %d) |\n", 100.0 * s.false_lines / std::max(1, s.extracted_lines), s.false_lines,
              s.extracted_lines);
  std::printf("| lines per scan | %.1f |\n", static_cast<double>(s.extracted_lines) / std::max(1, s.scans));
  if (opt.lines_file.empty()) {
    std::printf("| corner recall / false | %.1f%% (%d / %d) / %.1f%% (%d / %d) |\n",
                100.0 * s.found_corners / std::max(1, s.expected_corners), s.found_corners, s.expected_corners,
                100.0 * s.false_corners / std::max(1, s.extracted_corners), s.false_corners, s.extracted_corners);
    std::printf("| door recall / false openings | %.1f%% (%d / %d) / %.1f%% (%d / %d) |\n",
                100.0 * s.found_doors / std::max(1, s.visible_doors), s.found_doors, s.visible_doors,
                100.0 * s.false_openings / std::max(1, s.extracted_openings), s.false_openings, s.extracted_openings);
    std::printf("| extraction time per scan, median / mean | %.1f µs / %.1f µs |\n", percentile(s.micros, 0.5), mean(s.micros));
    std::printf("| false openings of kind DOOR or JUNCTION | %.1f%% (%d / %d) |\n",
                100.0 * s.false_typed_openings / std::max(1, s.typed_openings), s.false_typed_openings, s.typed_openings);
    std::printf("| place type right / unknown | %.1f%% / %.1f%% (%d scans in a region) |\n",
                100.0 * s.place_right / std::max(1, s.place_total), 100.0 * s.place_unknown / std::max(1, s.place_total),
                s.place_total);
    std::printf("| place type right in hallways / in rooms | %.1f%% (%d) / %.1f%% (%d) |\n",
                100.0 * s.hallway_right / std::max(1, s.hallway_scans), s.hallway_scans,
                100.0 * s.room_right / std::max(1, s.room_scans), s.room_scans);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (!parse(argc, argv, &opt)) {
    usage();
    return 2;
  }
  lf::FeatureExtractor::Params params;
  if (!opt.config.empty() && !loadParams(opt.config, &params)) return 1;
  rosbag::Bag bag;
  try {
    bag.open(opt.bag, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    std::fprintf(stderr, "evaluate_features: %s: %s\n", opt.bag.c_str(), e.what());
    return 1;
  }
  if (opt.world.empty()) return reportRealData(opt, params, &bag);

  bs::World world;
  try {
    world = bs::loadWorldFile(opt.world);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate_features: %s\n", e.what());
    return 1;
  }
  const bs::RayCaster2D caster(world);

  // External lines, keyed by evaluated-scan index.
  std::map<int, std::vector<Segment>> external;
  if (!opt.lines_file.empty() && !readExternalLines(opt.lines_file, &external)) return 1;
  std::ofstream dump;
  if (!opt.dump_file.empty()) dump.open(opt.dump_file);

  // Ground truth first (it may be recorded just after the scan of the same instant).
  const std::vector<std::pair<double, lf::Pose2D>> truth_track = truthTrack(&bag);
  if (truth_track.empty()) {
    std::fprintf(stderr, "evaluate_features: %s has no /ground_truth: record it with sim.launch record:=...\n",
                 opt.bag.c_str());
    return 1;
  }
  lf::FeatureExtractor extractor(params);
  lf::Features features;
  Stats s;
  int scan_number = 0, evaluated = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/scan"))) {
    auto scan = m.instantiate<sensor_msgs::LaserScan>();
    if (!scan) continue;
    if (scan_number++ % opt.stride != 0) continue;
    if (opt.max_scans > 0 && evaluated >= opt.max_scans) break;
    const double stamp = scan->header.stamp.toSec();
    auto it = std::lower_bound(truth_track.begin(), truth_track.end(), std::make_pair(stamp - 1e-6, lf::Pose2D{}),
                               [](const auto& a, const auto& b) { return a.first < b.first; });
    if (it == truth_track.end() || std::abs(it->first - stamp) > 1e-3) continue;  // no pose at this instant
    const lf::Pose2D laser = it->second;  // the laser sits at base_link's origin (urdf/robot.urdf)
    const std::vector<TrueLine> truth = visibleFaces(caster, laser, *scan, 6, 0.2);

    std::vector<Segment> lines;
    if (!opt.lines_file.empty()) {
      lines = external[evaluated];
      features.clear();
    } else {
      lf::ScanView v{scan->angle_min, scan->angle_increment, scan->range_min, scan->range_max, scan->ranges.data(),
                     scan->ranges.size()};
      const auto t0 = std::chrono::steady_clock::now();
      extractor.extract(v, &features);
      s.micros.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
      for (const auto& l : features.lines) lines.push_back({l.line, l.start, l.end});
    }
    if (dump.is_open()) dumpScan(*scan, &dump);
    scoreLines(lines, truth, &s);
    if (opt.lines_file.empty()) {
      scoreCorners(features.corners, truth, &s);
      scoreOpenings(features.openings, world, caster, laser, &s);
      scorePlaceType(features.place_type, world, laser, &s);
    }
    ++evaluated;
  }
  s.scans = evaluated;
  printReport(opt, s);
  return 0;
}
