#pragma once
/// A large, uninitialized array of trivially copyable values (megabytes: the row buffer and
/// the kept columns of samples.h5), aligned to 2 MiB and advised to the kernel as a candidate
/// for transparent huge pages (madvise MADV_HUGEPAGE; on this project's machines THP is in
/// "madvise" mode). First touching a 4 KiB page costs a page fault of about 2 us; 11 MB of
/// rows touched once cost 2700 of them, a 2 MiB page one. Where the kernel gives no huge
/// pages (THP "never", or memory too fragmented) it is an ordinary allocation. Pages are
/// taken from the kernel only where they are touched.
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

namespace poise {

template <class T>
class LargeBuffer {
  static_assert(std::is_trivially_copyable_v<T>, "LargeBuffer holds plain values only");

 public:
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;

  LargeBuffer() = default;
  explicit LargeBuffer(std::size_t n) : size_(n) {
    if (n == 0) return;
    const std::size_t bytes = (n * sizeof(T) + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, bytes);
    if (p == nullptr) throw std::bad_alloc();
    madvise(p, bytes, MADV_HUGEPAGE);  // a hint: failure (no THP in this kernel) changes nothing
    data_.reset(static_cast<T*>(p));
  }
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T[], Free> data_;
  std::size_t size_ = 0;
};

}  // namespace poise
