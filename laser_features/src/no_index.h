// kNone, the index that is no index, for the translation units of LineExtractor
// (src/line_extractor*.cpp); not installed.
#pragma once

#include <cstddef>
#include <limits>

namespace laser_features {

constexpr size_t kNone = std::numeric_limits<size_t>::max();

}  // namespace laser_features
