#pragma once
/// Progress of a long run on stderr: a live line with rate and ETA on a terminal,
/// a line per 10% otherwise (logs, CI).
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace poise::sampling {

class Progress {
 public:
  /// total: work units (samples); label: what is counted ("samples").
  Progress(std::string label, std::size_t total, bool enabled = true, std::FILE* out = stderr);
  /// Reports that `done` units of `total` are finished. Cheap; call after each block.
  void update(std::size_t done);
  /// Ends the line and prints the total time.
  void finish();
  double elapsed_seconds() const;

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  std::FILE* out_;
  bool tty_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace poise::sampling
