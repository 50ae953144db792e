#include "engine/results/chunk_codec.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/error.h"

namespace poise::engine {
namespace {

constexpr std::size_t kElement = sizeof(float);

void shuffle(const unsigned char* in, unsigned char* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < kElement; ++j) out[j * n + i] = in[i * kElement + j];
  }
}

void unshuffle(const unsigned char* in, unsigned char* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < kElement; ++j) out[i * kElement + j] = in[j * n + i];
  }
}

// Bytes a Huffman code of this plane's byte frequencies needs, at best (its entropy), estimated
// from at most kEntropySample evenly strided bytes: counting every byte of a 16384-row chunk
// cost a third of the encoding. The plug-in estimate of 4096 bytes reads at most 0.045 bits
// (0.6%) low for 256 equally likely values, far from the 3% margin that decides; the choice
// only changes how the bytes are coded, never the values, and the same plane always gets the
// same choice.
constexpr std::size_t kEntropySample = 4096;
double entropy_bytes(const unsigned char* plane, std::size_t n) {
  const std::size_t stride = std::max<std::size_t>(1, n / kEntropySample);
  std::size_t counts[256] = {}, m = 0;
  for (std::size_t i = 0; i < n; i += stride, ++m) ++counts[plane[i]];
  double bits = 0.0;
  const double mm = static_cast<double>(m);
  for (std::size_t c : counts) {
    if (c != 0) bits -= static_cast<double>(c) * std::log2(static_cast<double>(c) / mm);
  }
  return bits / mm / 8.0 * static_cast<double>(n);
}

}  // namespace

namespace {

// One zlib compressor per thread, reset between chunks: a fresh deflateInit2 allocates and
// clears about 256 KB (window, hash chains, symbol buffer), more than a small chunk costs to
// code. `level`/`strategy` are what it is set to now.
struct Compressor {
  z_stream z{};
  bool ready = false;
  int level = -1, strategy = -1;
  Compressor() = default;
  Compressor(const Compressor&) = delete;
  Compressor& operator=(const Compressor&) = delete;
  ~Compressor() { discard(); }
  // After a failure: a stream in an unknown state is not reused.
  void discard() {
    if (ready) deflateEnd(&z);
    z = z_stream{};
    ready = false;
    level = strategy = -1;
  }
  int start(int want_level) {
    if (!ready) {
      const int rc = deflateInit2(&z, want_level, Z_DEFLATED, 15, 8, Z_HUFFMAN_ONLY);
      if (rc != Z_OK) return rc;
      ready = true;
      level = want_level;
      strategy = Z_HUFFMAN_ONLY;
      return Z_OK;
    }
    const int rc = deflateReset(&z);
    return rc != Z_OK ? rc : set(want_level, Z_HUFFMAN_ONLY);
  }
  int set(int want_level, int want_strategy) {
    if (want_level == level && want_strategy == strategy) return Z_OK;
    const int rc = deflateParams(&z, want_level, want_strategy);
    if (rc == Z_OK) {
      level = want_level;
      strategy = want_strategy;
    }
    return rc;
  }
};

}  // namespace

std::string encode_chunk(std::span<const float> values, int level, std::size_t rows) {
  const std::size_t n = values.size();
  const std::size_t data = rows == 0 ? n : std::min(rows, n);
  const std::size_t bytes = n * kElement;
  thread_local std::vector<unsigned char> shuffled, out;
  thread_local Compressor c;
  shuffled.resize(bytes);
  shuffle(reinterpret_cast<const unsigned char*>(values.data()), shuffled.data(), n);
  int rc = c.start(level);
  if (rc != Z_OK) {
    c.discard();
    throw Error("samples.h5: zlib could not start (code " + std::to_string(rc) + ")");
  }
  z_stream& z = c.z;
  // Room for Huffman blocks no larger than stored ones (zlib falls back to stored blocks)
  // and the 5-byte header of each stored block of at most 65535 bytes.
  out.resize(deflateBound(&z, static_cast<uLong>(bytes)) + 5 * (bytes / 16384 + kElement) + 64);
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  // `count` bytes coded as set (the stream's last ones finish it).
  const auto code = [&](unsigned char* from, std::size_t count, int code_level, int strategy, bool last) {
    int r = c.set(code_level, strategy);
    if (r != Z_OK) return r;
    z.next_in = from;
    z.avail_in = static_cast<uInt>(count);
    r = deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
    return !last && r == Z_OK && z.avail_in != 0 ? Z_BUF_ERROR : r;
  };
  // Each plane's data bytes Huffman-coded or stored; a last chunk's zero padding as runs.
  for (std::size_t j = 0; j < kElement && rc == Z_OK; ++j) {
    unsigned char* plane = shuffled.data() + j * n;
    const bool huffman = entropy_bytes(plane, data) < kStoredAbove * static_cast<double>(data);
    const bool last = j + 1 == kElement;
    rc = huffman ? code(plane, data, level, Z_HUFFMAN_ONLY, last && data == n)
                 : code(plane, data, 0, Z_DEFAULT_STRATEGY, last && data == n);
    if (rc == Z_OK && data < n) rc = code(plane + data, n - data, level, Z_RLE, last);
  }
  const std::size_t size = z.total_out;
  if (rc != Z_STREAM_END) {
    c.discard();
    throw Error("samples.h5: zlib could not compress a chunk (code " + std::to_string(rc) + ")");
  }
  return std::string(reinterpret_cast<const char*>(out.data()), size);  // exactly its size: all wait for the write
}

void decode_chunk(std::string_view stored, std::uint32_t filter_mask, std::span<float> out, const std::string& what) {
  const std::size_t bytes = out.size() * kElement;
  const bool shuffled = (filter_mask & 1u) == 0;
  const bool deflated = (filter_mask & 2u) == 0;
  thread_local std::vector<unsigned char> plain;
  plain.resize(bytes);
  if (deflated) {
    uLongf size = static_cast<uLongf>(bytes);
    const int rc = uncompress(plain.data(), &size, reinterpret_cast<const Bytef*>(stored.data()),
                              static_cast<uLong>(stored.size()));
    if (rc != Z_OK || size != bytes) {
      throw Error(what + ": a chunk does not inflate to " + std::to_string(bytes) + " bytes (zlib code " +
                  std::to_string(rc) + "): the file is damaged");
    }
  } else {
    if (stored.size() != bytes)
      throw Error(what + ": a stored chunk has " + std::to_string(stored.size()) + " bytes, expected " +
                  std::to_string(bytes));
    std::memcpy(plain.data(), stored.data(), bytes);
  }
  if (shuffled) {
    unshuffle(plain.data(), reinterpret_cast<unsigned char*>(out.data()), out.size());
  } else {
    std::memcpy(out.data(), plain.data(), bytes);
  }
}

}  // namespace poise::engine
