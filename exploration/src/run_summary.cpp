#include "exploration/run_summary.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace exploration {

std::string jsonEscape(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(ch)));
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out;
}

std::string runSummaryJson(const Coordinator& c, bool complete, const std::string& text, double sim_s, double wall_s) {
  const CoordinatorStats& s = c.stats();
  const TopoGraph& g = c.graph();
  std::ostringstream f;
  f << "{\"complete\": " << (complete ? "true" : "false") << ", \"places\": " << g.placeCount()
    << ", \"places_entered_by_this_run\": " << s.places << ", \"rooms_entered_from_a_room\": " << s.inner_rooms
    << ", \"inner_doors_left\": " << s.inner_doors_left << ", \"inner_doors_given_up\": " << s.inner_doors_given_up
    << ", \"nodes\": " << g.nodes().size() << ", \"edges\": " << g.edges().size()
    << ", \"openings_explored\": " << g.exploredCount() << ", \"openings_unexplored\": " << g.unexploredCount()
    << ", \"travel_m\": " << s.travel << ", \"sim_time_s\": " << sim_s << ", \"wall_time_s\": " << wall_s
    << ", \"real_time_factor\": " << sim_s / std::max(wall_s, 1e-3) << ", \"rooms_left_early\": " << s.rooms_left_early
    << ", \"openings_given_up\": " << s.openings_given_up << ", \"openings_set_aside\": " << s.openings_set_aside
    << ", \"doors_of_mapped_rooms\": " << s.mapped_room_doors << ", \"belief_jumps\": " << s.belief_jumps << ", \"branch_turns_refused\": " << s.branch_turns_refused
    << ", \"room_free_area_m2\": " << s.room_free_area << ", \"peak_room_grid_bytes\": " << s.peak_room_bytes
    << ", \"text\": \"" << jsonEscape(text) << "\"}\n";
  return f.str();
}

}  // namespace exploration
