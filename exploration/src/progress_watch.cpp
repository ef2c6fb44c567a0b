#include "exploration/progress_watch.h"

#include <cstdio>

namespace exploration {

void ProgressWatch::mapChanged(const TopoGraph& graph) {
  now_.nodes = graph.nodes().size();
  now_.places = graph.placeCount();
  now_.openings_explored = graph.exploredCount();
  edge_length_ = graph.edgeLength();
}

bool ProgressWatch::stalled(double hallway_travel, bool on_frontier, int openings_given_up) {
  now_.openings_given_up = openings_given_up;
  if (!started_ || on_frontier || !(now_ == last_)) {
    started_ = true;
    last_ = now_;
    progress_travel_ = hallway_travel;
  }
  since_ = hallway_travel - progress_travel_;
  return edge_length_ > 0.0 && since_ > window();
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
