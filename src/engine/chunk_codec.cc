#include "engine/chunk_codec.h"

#include <zlib.h>

#include <cstring>
#include <vector>

#include "core/error.h"

namespace poise::studies {
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

}  // namespace

std::string encode_chunk(std::span<const float> values, int level) {
  const std::size_t bytes = values.size() * kElement;
  std::vector<unsigned char> shuffled(bytes);
  shuffle(reinterpret_cast<const unsigned char*>(values.data()), shuffled.data(), values.size());
  z_stream z{};
  int rc = deflateInit2(&z, level, Z_DEFLATED, 15, 8, Z_HUFFMAN_ONLY);
  require(rc == Z_OK, "samples.h5: zlib could not start (code " + std::to_string(rc) + ")");
  std::string out(deflateBound(&z, static_cast<uLong>(bytes)), '\0');
  z.next_in = shuffled.data();
  z.avail_in = static_cast<uInt>(bytes);
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  rc = deflate(&z, Z_FINISH);
  const std::size_t size = z.total_out;
  deflateEnd(&z);
  require(rc == Z_STREAM_END, "samples.h5: zlib could not compress a chunk (code " + std::to_string(rc) + ")");
  return std::string(out.data(), size);  // exactly its size: 169 of them wait for the write
}

void decode_chunk(std::string_view stored, std::uint32_t filter_mask, std::span<float> out, const std::string& what) {
  const std::size_t bytes = out.size() * kElement;
  const bool shuffled = (filter_mask & 1u) == 0;
  const bool deflated = (filter_mask & 2u) == 0;
  std::vector<unsigned char> plain(bytes);
  if (deflated) {
    uLongf size = static_cast<uLongf>(bytes);
    const int rc = uncompress(plain.data(), &size, reinterpret_cast<const Bytef*>(stored.data()),
                              static_cast<uLong>(stored.size()));
    if (rc != Z_OK || size != bytes) {
      throw Error(what + ": a chunk does not inflate to " + std::to_string(bytes) + " bytes (zlib code " +
                  std::to_string(rc) + "): the file is damaged");
    }
  } else {
    if (stored.size() != bytes) throw Error(what + ": a stored chunk has " + std::to_string(stored.size()) +
                                            " bytes, expected " + std::to_string(bytes));
    std::memcpy(plain.data(), stored.data(), bytes);
  }
  if (shuffled) {
    unshuffle(plain.data(), reinterpret_cast<unsigned char*>(out.data()), out.size());
  } else {
    std::memcpy(out.data(), plain.data(), bytes);
  }
}

}  // namespace poise::studies
