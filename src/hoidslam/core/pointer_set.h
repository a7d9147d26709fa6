#pragma once
// A set of pointers in one flat table (open addressing, linear probing): no allocation per element, where
// std::unordered_set makes one for every insert. For the tens of thousands of map points a frame's tracking looks
// at, once each, this is about a millisecond a frame.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hoidslam::core {

template <typename T>
class PointerSet {
 public:
  // An empty set with room for `expected` elements before it grows.
  explicit PointerSet(std::size_t expected = 0) { Rehash(std::bit_ceil(2 * expected + 16)); }

  // Adds `p`; false when it was there already. nullptr is never an element: inserting it returns false.
  bool Insert(const T* p) {
    if (p == nullptr) return false;
    if (2 * (size_ + 1) > slots_.size()) Rehash(2 * slots_.size());
    if (!Place(p)) return false;
    ++size_;
    return true;
  }

  bool Contains(const T* p) const {
    if (p == nullptr) return false;
    for (std::size_t i = Slot(p);; i = (i + 1) & mask()) {
      if (slots_[i] == p) return true;
      if (slots_[i] == nullptr) return false;
    }
  }

  std::size_t size() const { return size_; }

 private:
  std::vector<const T*> slots_;
  std::size_t size_ = 0;

  std::size_t mask() const { return slots_.size() - 1; }
  // Fibonacci hashing of the address: the low bits of a pointer are alignment, the high bits of the product mix
  // all of them.
  std::size_t Slot(const T* p) const {
    const auto bits = static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(p)) * 0x9E3779B97F4A7C15ULL;
    return static_cast<std::size_t>(bits >> (64 - std::countr_zero(slots_.size()))) & mask();
  }
  // Puts `p` in its slot unless it is there: true when it was placed.
  bool Place(const T* p) {
    for (std::size_t i = Slot(p);; i = (i + 1) & mask()) {
      if (slots_[i] == p) return false;
      if (slots_[i] == nullptr) {
        slots_[i] = p;
        return true;
      }
    }
  }
  void Rehash(std::size_t capacity) {
    std::vector<const T*> old(capacity, nullptr);
    old.swap(slots_);
    for (const T* p : old) {
      if (p != nullptr) Place(p);
    }
  }
};

}  // namespace hoidslam::core
