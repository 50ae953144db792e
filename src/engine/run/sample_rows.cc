#include "engine/run/sample_rows.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <charconv>

#include "engine/results/result_io.h"

namespace poise::engine {
namespace {
constexpr std::size_t kRowsPerPiece = 64;
}  // namespace

SampleRowWriter::SampleRowWriter(CheckedFile& csv, std::size_t rows_on_disk, bool solver_column)
    : csv_(csv), rows_on_disk_(rows_on_disk), solver_column_(solver_column) {}

std::string SampleRowWriter::format(std::span<const SampleResult> block) const {
  const std::size_t n_pieces = (block.size() + kRowsPerPiece - 1) / kRowsPerPiece;
  if (n_pieces <= 1) {  // a procedure's small block: no task to hand out
    std::string text;
    if (n_pieces == 1) format_piece(block, 0, text);
    return text;
  }
  std::vector<std::string> pieces(n_pieces);
  tbb::parallel_for(std::size_t{0}, n_pieces, [&](std::size_t piece) { format_piece(block, piece, pieces[piece]); });
  std::size_t bytes = 0;
  for (const auto& piece : pieces) bytes += piece.size();
  std::string text;
  text.reserve(bytes);
  for (const auto& piece : pieces) text += piece;
  return text;
}

SampleSink SampleRowWriter::sink() {
  return {[this](std::span<const SampleResult> block) { return format(block); },
          [this](std::span<const SampleResult>, std::string_view rows) { write(rows); }};
}

void SampleRowWriter::format_piece(std::span<const SampleResult> block, std::size_t piece, std::string& text) const {
  std::vector<char> row;
  const std::size_t end = std::min(block.size(), (piece + 1) * kRowsPerPiece);
  for (std::size_t k = piece * kRowsPerPiece; k < end; ++k) {
    const SampleResult& s = block[k];
    if (s.index < rows_on_disk_) continue;
    // The numbers into one buffer, then one append (not one per number).
    row.resize(64 + kCsvNumberChars * (s.inputs.size() + s.outputs.size()));
    char* at = std::to_chars(row.data(), row.data() + 24, s.index).ptr;
    const std::string_view status = s.ok ? ",ok" : ",failed";
    at = std::copy(status.begin(), status.end(), at);
    for (double v : s.inputs) at = put_csv_number(at, v);
    for (double v : s.outputs) at = put_csv_number(at, v);
    if (solver_column_) {
      *at++ = ',';
      at = std::to_chars(at, at + 24, s.solver_steps).ptr;
    }
    *at++ = ',';
    text.append(row.data(), at);
    if (!s.message.empty()) text += csv_text(s.message);
    text += '\n';
  }
}

}  // namespace poise::engine
