// File helpers shared by every map file of the stack (DESIGN.md: maps persist to files written
// atomically — write a temporary file, fsync, rename — and a corrupt file is detected).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace laser_features {

/// CRC-32 (IEEE 802.3 polynomial, as zlib's crc32), continuing from `crc` (0 to start).
uint32_t crc32(const void* data, size_t size, uint32_t crc = 0);

/// Writes `bytes` to `path` atomically: `path`.tmp is written and fsync'ed, then renamed over
/// `path` and the directory fsync'ed. On failure returns false with `error` saying what failed
/// (without the path: callers prefix their own context); `path` is untouched and no .tmp is left.
bool writeFileAtomically(const std::string& path, const std::string& bytes, std::string* error);

/// Reads the whole file; on failure returns false with `error` ("cannot open: <reason>").
bool readWholeFile(const std::string& path, std::string* bytes, std::string* error);

}  // namespace laser_features
