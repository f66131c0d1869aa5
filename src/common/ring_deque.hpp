// A double-ended queue on one growable ring of reused slots: no allocation once it has grown.
#pragma once

#include <cstddef>
#include <iterator>
#include <utility>
#include <vector>

namespace gm {

/// What the planner's look-ahead windows need of std::deque (push at the back, pop at the front,
/// random access in order) without its allocation of a node per element: std::deque keeps one
/// element of more than 512 bytes a node and frees the node when it is popped. Here the
/// elements live in a ring of slots (a power of two) that doubles when full and never shrinks;
/// a popped element stays in its slot until a push overwrites it (by assignment).
template <typename T>
class RingDeque {
 public:
  template <bool Const>
  class Iter {
   public:
    using iterator_category = std::random_access_iterator_tag;
    using value_type = T;
    using difference_type = std::ptrdiff_t;
    using pointer = std::conditional_t<Const, const T*, T*>;
    using reference = std::conditional_t<Const, const T&, T&>;
    using Owner = std::conditional_t<Const, const RingDeque, RingDeque>;

    Iter() = default;
    Iter(Owner* q, std::size_t i) : q_(q), i_(i) {}
    operator Iter<true>() const { return Iter<true>(q_, i_); }  // NOLINT: as std's iterators
    reference operator*() const { return (*q_)[i_]; }
    pointer operator->() const { return &(*q_)[i_]; }
    reference operator[](difference_type n) const {
      return (*q_)[i_ + static_cast<std::size_t>(n)];
    }
    Iter& operator++() { return ++i_, *this; }
    Iter& operator--() { return --i_, *this; }
    Iter operator++(int) { return Iter(q_, i_++); }
    Iter operator--(int) { return Iter(q_, i_--); }
    Iter& operator+=(difference_type n) { return i_ += static_cast<std::size_t>(n), *this; }
    Iter& operator-=(difference_type n) { return i_ -= static_cast<std::size_t>(n), *this; }
    friend Iter operator+(Iter a, difference_type n) { return a += n; }
    friend Iter operator+(difference_type n, Iter a) { return a += n; }
    friend Iter operator-(Iter a, difference_type n) { return a -= n; }
    friend difference_type operator-(const Iter& a, const Iter& b) {
      return static_cast<difference_type>(a.i_) - static_cast<difference_type>(b.i_);
    }
    friend bool operator==(const Iter& a, const Iter& b) { return a.i_ == b.i_; }
    friend bool operator!=(const Iter& a, const Iter& b) { return a.i_ != b.i_; }
    friend bool operator<(const Iter& a, const Iter& b) { return a.i_ < b.i_; }
    friend bool operator>(const Iter& a, const Iter& b) { return a.i_ > b.i_; }
    friend bool operator<=(const Iter& a, const Iter& b) { return a.i_ <= b.i_; }
    friend bool operator>=(const Iter& a, const Iter& b) { return a.i_ >= b.i_; }

   private:
    Owner* q_ = nullptr;
    std::size_t i_ = 0;  ///< position from the front
  };
  using iterator = Iter<false>;
  using const_iterator = Iter<true>;

  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return slots_[(head_ + i) & mask_]; }
  const T& operator[](std::size_t i) const { return slots_[(head_ + i) & mask_]; }
  T& front() { return (*this)[0]; }
  const T& front() const { return (*this)[0]; }
  T& back() { return (*this)[size_ - 1]; }
  const T& back() const { return (*this)[size_ - 1]; }

  template <typename U>
  void push_back(U&& v) {
    if (size_ == slots_.size()) grow();
    slots_[(head_ + size_) & mask_] = std::forward<U>(v);
    ++size_;
  }
  /// Appends an element and returns its slot, to be assigned in place (it still holds whatever
  /// was last there): what push_back does without a temporary.
  T& push_back_slot() {
    if (size_ == slots_.size()) grow();
    return slots_[(head_ + size_++) & mask_];
  }
  void pop_front() {
    head_ = (head_ + 1) & mask_;
    --size_;
  }
  void clear() { head_ = size_ = 0; }

  iterator begin() { return iterator(this, 0); }
  iterator end() { return iterator(this, size_); }
  const_iterator begin() const { return const_iterator(this, 0); }
  const_iterator end() const { return const_iterator(this, size_); }
  std::reverse_iterator<iterator> rbegin() { return std::reverse_iterator<iterator>(end()); }
  std::reverse_iterator<iterator> rend() { return std::reverse_iterator<iterator>(begin()); }

 private:
  void grow() {
    std::vector<T> bigger(slots_.empty() ? 8 : 2 * slots_.size());
    for (std::size_t i = 0; i < size_; ++i) bigger[i] = std::move((*this)[i]);
    slots_ = std::move(bigger);
    head_ = 0;
    mask_ = slots_.size() - 1;
  }

  std::vector<T> slots_;
  std::size_t head_ = 0, size_ = 0, mask_ = 0;
};

}  // namespace gm
