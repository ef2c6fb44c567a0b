#include "lockstep/counts.h"

namespace lockstep {

bool covers(const Counts& received, const Counts& announced, const std::set<std::string>& watched, std::string* why) {
  for (const auto& [topic, n] : announced) {
    if (watched.count(topic) == 0) continue;
    const auto r = received.find(topic);
    const uint64_t got = r == received.end() ? 0 : r->second;
    if (got < n) {
      if (why != nullptr) *why = topic + ": " + std::to_string(got) + " of " + std::to_string(n);
      return false;
    }
  }
  return true;
}

Counts maxCounts(const Counts& a, const Counts& b) {
  Counts out = a;
  for (const auto& [topic, n] : b) out[topic] = std::max(out[topic], n);
  return out;
}

Counts sumCounts(const Counts& a, const Counts& b) {
  Counts out = a;
  for (const auto& [topic, n] : b) out[topic] += n;
  return out;
}

}  // namespace lockstep
