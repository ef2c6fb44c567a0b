#include "exploration/progress_watch.h"

#include <cstdio>

namespace exploration {

bool ProgressWatch::stalled(double hallway_travel, bool on_frontier, const ProgressCounts& counts,
                            double edge_length) {
  if (!started_ || on_frontier || !(counts == last_)) {
    started_ = true;
    last_ = counts;
    progress_travel_ = hallway_travel;
  }
  edge_length_ = edge_length;
  window_ = walks_ * edge_length;
  since_ = hallway_travel - progress_travel_;
  return edge_length > 0.0 && since_ > window_;
}

std::string ProgressWatch::why() const {
  char text[200];
  std::snprintf(text, sizeof(text),
                "no new node or place and no opening explored or given up over %.0f m of hallway travel (%d times "
                "the map's %.0f m of hallways: the belief does not find the openings left)",
                since_, walks_, edge_length_);
  return text;
}

}  // namespace exploration
