#pragma once
/// samples.csv rows of each finished block: "index,status,<inputs>,<outputs>[,solver_steps],message".
/// The rows' text is made where the block was computed (format: on the MPI rank that computed
/// it, on the threads of the caller's task arena, 64 rows to a piece; a LOS sample has some 60
/// numbers, a procedure's a few dozen) and written on rank 0 in sample order (write). Rows a
/// resumed run already has on disk (indices below `rows_on_disk`) are skipped, so a study that
/// recomputes them writes none twice.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/kind_interface/procedure_study.h"
#include "engine/results/checked_file.h"

namespace poise::engine {

class SampleRowWriter {
 public:
  SampleRowWriter(CheckedFile& csv, std::size_t rows_on_disk, bool solver_column);
  /// One block's rows, on the threads of the caller's task arena (const: any rank, any thread).
  std::string format(std::span<const SampleResult> block) const;
  /// Writes a block's formatted rows (rank 0, in sample order); the first refused write throws
  /// WriteError.
  void write(std::string_view rows) { csv_.write(rows); }
  /// Both: the sink of a run made in this process alone.
  SampleSink sink();

 private:
  void format_piece(std::span<const SampleResult> block, std::size_t piece, std::string& text) const;

  CheckedFile& csv_;
  std::size_t rows_on_disk_;
  bool solver_column_;
};

}  // namespace poise::engine
