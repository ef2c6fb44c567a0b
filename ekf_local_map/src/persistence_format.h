// The places file's record sizes and flags, for the translation units of the persistence code
// (src/persistence*.cpp); not installed. The format: persistence.h.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ekf_local_map {

// Record sizes (see persistence.h).
constexpr size_t kLineRecordBytes = 6 * 8;
constexpr size_t kDoorRecordBytes = 4 + 9 * 8;
constexpr size_t kCompactRobotCovBytes = 6 * 4;
constexpr size_t kCompactLineBytes = 7 * 4;       // version 3: the extent as two positions on the line
constexpr size_t kCompactLineBytesV2 = 9 * 4;     // version 2: the extent as two points
constexpr size_t kCompactDoorBytes = 4 + 9 * 4;

constexpr uint32_t kFlagRelocationPending = 1u;
constexpr uint32_t kFlagCompact = 2u;  // version 2 on

}  // namespace ekf_local_map
