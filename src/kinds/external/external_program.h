#pragma once
/// A user's program that computes samples, spoken to through its standard input and output:
/// no shell, no temporary result files to race on. One process per thread, started at its first
/// batch and kept for the next ones; a process that crashed or timed out is ended and a new one
/// started for the next batch.
///
/// The protocol (docs/own-mechanism.md, "An external program"): Poise writes a batch of
/// requests, one JSON line each,
///     {"sample": 17, "inputs": {"shaft": 208.01, "ring": 1.77}}
/// with every parameter in the unit its value is written in the model file; the program
/// answers one line per request, in any order,
///     {"sample": 17, "outputs": {"gap": 0.41}}          (in the outputs' declared units)
///     {"sample": 17, "failed": "the rings interfere"}   (the sample fails with this reason)
/// and flushes its output after each batch. Anything it writes to standard error is kept (the
/// last 2 kB) and quoted when it fails.
#include <sys/types.h>

#include <string>
#include <vector>

namespace poise::kinds::external {

/// One request's answer: its output values in declared order, or why it has none.
struct Answer {
  std::vector<double> outputs;
  std::string failed;  ///< "" when answered
};

class ExternalProgram {
 public:
  /// `argv[0]` is found on PATH unless it holds a '/' (then it is relative to `folder`), which is
  /// also the program's working directory. `timeout_s`: the longest wait for one answer line
  /// (10 s more for the first answer after the program starts).
  ExternalProgram(std::vector<std::string> argv, std::string folder, std::vector<std::string> input_names,
                  std::vector<std::string> output_names, double timeout_s);
  ~ExternalProgram();
  ExternalProgram(const ExternalProgram&) = delete;
  ExternalProgram& operator=(const ExternalProgram&) = delete;

  /// The answers to a batch: `inputs` row-major (one row of input_names per id). A sample the
  /// program did not answer (it crashed, timed out or wrote what is not the protocol) gets the
  /// reason; the program is then started again for the next batch.
  std::vector<Answer> evaluate(const std::vector<std::size_t>& ids, const std::vector<double>& inputs);

  /// The command line as the user would type it, with the folder it runs in.
  static std::string command_line(const std::vector<std::string>& argv, const std::string& folder);

 private:
  void start();
  void stop(bool kill_now);
  std::string stderr_tail() const;
  // Writes `requests` and reads lines until `expected` answers or a fault; returns the fault ("" if none).
  std::string exchange(const std::string& requests, std::size_t expected, std::vector<std::string>& lines);

  std::vector<std::string> argv_;
  std::string folder_;
  std::vector<std::string> input_names_, output_names_;
  double timeout_s_;
  pid_t pid_ = -1;
  int to_child_ = -1, from_child_ = -1, err_child_ = -1;
  std::string pending_out_, err_;
  bool just_started_ = false;
};

}  // namespace poise::kinds::external
