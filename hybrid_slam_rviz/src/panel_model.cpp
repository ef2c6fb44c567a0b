#include "hybrid_slam_rviz/panel_model.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace hybrid_slam_rviz {

namespace {
std::string format(const char* f, double a, double b = 0.0) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), f, a, b);
  return buf;
}
}  // namespace

StatusText describe(const StatusFields& s) {
  StatusText t;
  t.mode = s.mode + (s.state.empty() ? "" : " - " + s.state);
  t.where = "place " + (s.place >= 0 ? std::to_string(s.place) : std::string("-")) + ", node " +
            (s.node >= 0 ? std::to_string(s.node) : std::string("- (unconfident)"));
  t.map = std::to_string(s.places) + " places, " + std::to_string(s.nodes) + " nodes, openings " +
          std::to_string(s.explored) + " explored / " + std::to_string(s.unexplored) + " unexplored";
  t.travel = format("%.1f m travelled, real-time factor %.1f", s.travel_m, s.real_time_factor);
  return t;
}

std::string beliefText(double entropy, double entropy_max, bool confident) {
  if (!std::isfinite(entropy)) return "no belief yet";
  return format("U %.2f of U_max %.2f nats: ", entropy, entropy_max) + (confident ? "confident" : "unconfident");
}

std::optional<int> placeOfFrame(const std::string& frame, const std::string& prefix) {
  const std::string name = !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  int id = 0;
  for (size_t i = prefix.size(); i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9' || id > 100000000) return std::nullopt;
    id = id * 10 + (name[i] - '0');
  }
  return id;
}

int nearestPlace(const std::vector<PlaceFrame>& places, double x, double y) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (const PlaceFrame& p : places) {
    const double d = std::hypot(p.pose.x - x, p.pose.y - y);
    if (d < best_d) {
      best_d = d;
      best = p.id;
    }
  }
  return best;
}

Pose2D goalInPlace(const Pose2D& place_pose, const Pose2D& goal) {
  return laser_features::compose(laser_features::inverse(place_pose), goal);
}

}  // namespace hybrid_slam_rviz
