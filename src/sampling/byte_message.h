#pragma once
/// The bytes of a message between the ranks of a run (sampling/distributed.h): ByteWriter puts
/// plain fields, vectors of them and strings; ByteReader takes them back in the same order and
/// refuses a message that ends early.
#include <cstddef>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace poise::sampling {

/// Bytes of a message between MPI ranks (a sample result, a share of statistics): plain
/// fields, vectors of them and strings, read back in the order written.
class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put(v.size());
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  template <class T>
  void put_span(std::span<const T> v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(v.size());
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put_string(const std::string& s) {
    put(s.size());
    out_.append(s);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view in) : in_(in) {}
  template <class T>
  T get() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  void get_vector(std::vector<T>& v) {
    v.resize(get<std::size_t>());
    take(v.data(), v.size() * sizeof(T));
  }
  void get_string(std::string& s) {
    s.resize(get<std::size_t>());
    take(s.data(), s.size());
  }
  bool done() const { return pos_ == in_.size(); }

 private:
  void take(void* dst, std::size_t n) {
    require(pos_ + n <= in_.size(), "corrupt message from an MPI rank");
    if (n > 0) std::memcpy(dst, in_.data() + pos_, n);
    pos_ += n;
  }
  std::string_view in_;
  std::size_t pos_ = 0;
};

}  // namespace poise::sampling
