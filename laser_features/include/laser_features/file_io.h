// File helpers shared by every map file of the stack (DESIGN.md: maps persist to files written
// atomically — write a temporary file, fsync, rename — and a corrupt file is detected).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
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

/// An angle of (-pi, pi] rounded to float32 and still inside (-pi, pi]: rounding can carry a value
/// near either end past it (float(pi) > pi), so such a value goes one float towards zero (at most
/// 2.4e-7 rad away from `a` in all).
inline float angleToFloat(double a) {
  constexpr double kPiHere = 3.14159265358979323846;
  float f = static_cast<float>(a);
  if (double(f) > kPiHere || double(f) <= -kPiHere) f = std::nextafter(f, 0.0f);
  return f;
}

/// Appends little-endian binary numbers to a string (the body of the map files).
class BinaryWriter {
 public:
  explicit BinaryWriter(std::string* out) : out_(out) {}
  void u8(uint8_t v) { out_->push_back(char(v)); }
  void u32(uint32_t v) {
    for (int b = 0; b < 4; ++b) out_->push_back(char((v >> (8 * b)) & 0xffu));
  }
  void i32(int32_t v) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u32(bits);
  }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int b = 0; b < 8; ++b) out_->push_back(char((bits >> (8 * b)) & 0xffu));
  }
  /// IEEE-754 binary32 (rounded to nearest from double).
  void f32(float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u32(bits);
  }

 private:
  std::string* out_;
};

/// Bounds-checked little-endian reader of bytes [begin, end) of a string; the first failure
/// (the data ends early, a non-finite number) is kept in error() and later reads return 0.
class BinaryReader {
 public:
  BinaryReader(const std::string& bytes, size_t begin, size_t end) : bytes_(bytes), pos_(begin), end_(end) {}
  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  size_t position() const { return pos_; }
  size_t remaining() const { return end_ - pos_; }
  void fail(const std::string& what) {
    if (error_.empty()) error_ = what;
  }
  uint8_t u8(const char* what) {
    if (!need(1, what)) return 0;
    return uint8_t(bytes_[pos_++]);
  }
  uint32_t u32(const char* what) {
    if (!need(4, what)) return 0;
    uint32_t v = 0;
    for (int b = 0; b < 4; ++b) v |= uint32_t(uint8_t(bytes_[pos_ + size_t(b)])) << (8 * b);
    pos_ += 4;
    return v;
  }
  int32_t i32(const char* what) {
    const uint32_t bits = u32(what);
    int32_t v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  double f64(const char* what) {
    if (!need(8, what)) return 0.0;
    uint64_t bits = 0;
    for (int b = 0; b < 8; ++b) bits |= uint64_t(uint8_t(bytes_[pos_ + size_t(b)])) << (8 * b);
    pos_ += 8;
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) fail(std::string("non-finite number in ") + what + " at byte " + std::to_string(pos_ - 8));
    return v;
  }
  float f32(const char* what) {
    const uint32_t bits = u32(what);
    float v;
    std::memcpy(&v, &bits, sizeof v);
    if (ok() && !std::isfinite(v)) {
      fail(std::string("non-finite number in ") + what + " at byte " + std::to_string(pos_ - 4));
    }
    return ok() ? v : 0.0f;
  }
  bool need(size_t n, const char* what) {
    if (!ok()) return false;
    if (remaining() < n) {
      fail(std::string("the file ends early (truncated?) while reading ") + what + " at byte " +
           std::to_string(pos_));
      return false;
    }
    return true;
  }

 private:
  const std::string& bytes_;
  size_t pos_;
  size_t end_;
  std::string error_;
};

}  // namespace laser_features
