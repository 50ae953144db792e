#pragma once
/// The filters of the chunks of samples.h5, applied by Poise itself (HDF5's direct chunk
/// I/O) so that threads compress and decompress chunks in parallel, outside HDF5's lock:
///   1. byte shuffle (HDF5's H5Z_FILTER_SHUFFLE): byte j of element i goes to j * n + i, so the
///      slowly varying exponent bytes of a float column sit together;
///   2. deflate (H5Z_FILTER_DEFLATE): a zlib stream, Huffman coding only (Z_HUFFMAN_ONLY):
///      float noise has no repeated strings for LZ77 to find, and on the LOS grid values this is
///      2.3x faster than the default strategy at level 1 for a smaller file (79% of the raw
///      bytes against 82%). A byte plane whose Huffman code could not save 3% of it (its byte
///      entropy, estimated from at most 4096 evenly strided bytes, at least 0.97 x 8 bits:
///      the low mantissa bytes of noisy values) goes into
///      stored blocks instead (zlib level 0, switched by deflateParams within the one stream):
///      copying it costs a fraction of coding it for the same size. Any zlib reader inflates it.
/// The dataset's creation property list declares the same pipeline (H5Pset_shuffle,
/// H5Pset_deflate), so any HDF5 reader (h5py, pandas via h5py, h5dump) reads the chunks.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace poise::engine {

/// zlib level of samples.h5 (declared in the file; with Huffman coding only it changes little).
inline constexpr int kChunkDeflateLevel = 1;

/// A byte plane is stored, not Huffman-coded, when its entropy is at least this share of 8 bits.
inline constexpr double kStoredAbove = 0.97;

/// Shuffled and deflated bytes of a chunk of 4-byte values, of which the first `rows` are data
/// (all when 0): a dataset's last chunk is padded with zeros past its rows, which no reader
/// sees. Each plane's data bytes are stored or Huffman-coded as they decide, and the padding is
/// coded as runs (Z_RLE): judged and coded with the padding, the noisy low planes of a chunk
/// mostly of zeros were Huffman-coded, and a last chunk took twice a full one's time.
std::string encode_chunk(std::span<const float> values, int level = kChunkDeflateLevel, std::size_t rows = 0);

/// The values of a stored chunk. filter_mask is HDF5's: bit 0 set = shuffle skipped, bit 1
/// set = deflate skipped. Throws poise::Error (naming `what`) on corrupt or short data.
void decode_chunk(std::string_view stored, std::uint32_t filter_mask, std::span<float> out, const std::string& what);

}  // namespace poise::engine
