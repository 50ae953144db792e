#pragma once
/// samples.csv rows of each finished block: "index,status,<inputs>,<outputs>[,solver_steps],message".
/// The rows' text is made on the run's threads (a LOS sample has some 60 numbers, a
/// procedure's a few dozen), 64 rows to a piece, and the pieces written in order; their strings
/// keep their capacity from block to block. Rows a resumed run already has on disk (indices
/// below `rows_on_disk`) are skipped, so a study that recomputes them writes none twice.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "engine/kind_interface/procedure_study.h"
#include "engine/results/checked_file.h"

namespace poise::engine {

class SampleRowWriter {
 public:
  SampleRowWriter(CheckedFile& csv, int threads, std::size_t rows_on_disk, bool solver_column);
  /// Formats and writes one block (in sample order); the first refused write throws WriteError.
  void operator()(std::span<const SampleResult> block);

 private:
  void format_piece(std::span<const SampleResult> block, std::size_t piece);

  CheckedFile& csv_;
  tbb::task_arena arena_;
  std::size_t rows_on_disk_;
  bool solver_column_;
  std::vector<std::string> pieces_;
};

}  // namespace poise::engine
