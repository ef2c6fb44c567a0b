// Test support: replaces the global operator new/delete with counting ones. Include it in exactly one
// source file of a test binary (the replacement is program-wide); read allocationCount() around the
// code that must not allocate.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace laser_features {
namespace testing {

inline std::atomic<long>& allocationCounter() {
  static std::atomic<long> count{0};
  return count;
}
inline long allocationCount() { return allocationCounter().load(); }

inline void* countedAllocation(std::size_t size) {
  allocationCounter().fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
inline void* countedAlignedAllocation(std::size_t size, std::align_val_t alignment) {
  allocationCounter().fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(alignment);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}

}  // namespace testing
}  // namespace laser_features

void* operator new(std::size_t size) { return laser_features::testing::countedAllocation(size); }
void* operator new[](std::size_t size) { return laser_features::testing::countedAllocation(size); }
void* operator new(std::size_t size, std::align_val_t a) {
  return laser_features::testing::countedAlignedAllocation(size, a);
}
void* operator new[](std::size_t size, std::align_val_t a) {
  return laser_features::testing::countedAlignedAllocation(size, a);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
