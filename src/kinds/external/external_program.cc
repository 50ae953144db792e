#include "kinds/external/external_program.h"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "core/error.h"

extern char** environ;

namespace poise::kinds::external {
namespace {
using nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kStderrKept = 2048;
constexpr double kStartAllowance = 10.0;  // s

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

std::string shown(const std::string& line) {
  return line.size() > 200 ? "\"" + line.substr(0, 200) + "...\"" : "\"" + line + "\"";
}

std::string exit_text(int status) {
  if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "ended";
}

}  // namespace

ExternalProgram::ExternalProgram(std::vector<std::string> argv, std::string folder,
                                 std::vector<std::string> input_names, std::vector<std::string> output_names,
                                 double timeout_s)
    : argv_(std::move(argv)),
      folder_(std::move(folder)),
      input_names_(std::move(input_names)),
      output_names_(std::move(output_names)),
      timeout_s_(timeout_s) {}

ExternalProgram::~ExternalProgram() { stop(false); }

std::string ExternalProgram::command_line(const std::vector<std::string>& argv, const std::string& folder) {
  std::string s;
  for (const std::string& a : argv) {
    const bool plain = !a.empty() && a.find_first_of(" \t\"'\\$`") == std::string::npos;
    s += (s.empty() ? "" : " ") + (plain ? a : json(a).dump());
  }
  return s + " (in " + folder + ")";
}

void ExternalProgram::start() {
  // A program that dies mid-batch must not take Poise with it: writing to its closed pipe
  // then fails with EPIPE instead of raising SIGPIPE.
  static const bool sigpipe_ignored = [] { return std::signal(SIGPIPE, SIG_IGN) != SIG_ERR; }();
  (void)sigpipe_ignored;
  int in[2], out[2], err[2];
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(err, O_CLOEXEC) != 0) {
    throw Error(std::string("cannot make pipes for the program: ") + std::strerror(errno));
  }
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, in[0], 0);
  posix_spawn_file_actions_adddup2(&fa, out[1], 1);
  posix_spawn_file_actions_adddup2(&fa, err[1], 2);
  posix_spawn_file_actions_addchdir_np(&fa, folder_.c_str());
  std::string program = argv_[0];
  if (program.find('/') != std::string::npos && !std::filesystem::path(program).is_absolute()) {
    program = (std::filesystem::path(folder_) / program).string();
  }
  std::vector<char*> args;
  for (std::string& a : argv_) args.push_back(a.data());
  args.push_back(nullptr);
  const int rc = posix_spawnp(&pid_, program.c_str(), &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(in[0]);
  ::close(out[1]);
  ::close(err[1]);
  to_child_ = in[1];
  from_child_ = out[0];
  err_child_ = err[0];
  if (rc != 0) {
    pid_ = -1;
    stop(true);
    throw Error("cannot start the program " + command_line(argv_, folder_) + ": " + std::strerror(rc));
  }
  for (int fd : {to_child_, from_child_, err_child_}) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
  pending_out_.clear();
  err_.clear();
  just_started_ = true;
}

void ExternalProgram::stop(bool kill_now) {
  close_fd(to_child_);  // end of input: a well-behaved program ends
  if (pid_ > 0) {
    int status = 0;
    if (kill_now) ::kill(pid_, SIGKILL);
    // Up to a second for the program to end by itself, then it is killed.
    const auto until = Clock::now() + std::chrono::seconds(1);
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (Clock::now() > until) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
        break;
      }
      ::usleep(2000);
    }
  }
  pid_ = -1;
  close_fd(from_child_);
  close_fd(err_child_);
}

std::string ExternalProgram::stderr_tail() const {
  if (err_.empty()) return "";
  std::string tail = err_;
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == ' ')) tail.pop_back();
  return "; its standard error ends: " + shown(tail);
}

std::string ExternalProgram::exchange(const std::string& requests, std::size_t expected,
                                      std::vector<std::string>& lines) {
  std::size_t written = 0;
  // The first answer after a start waits longer: a program's start (an interpreter importing
  // its libraries) is not an answer's wait.
  auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s_ + (just_started_ ? kStartAllowance : 0.0));
  just_started_ = false;
  char buf[65536];
  for (;;) {
    pollfd fds[3];
    nfds_t n = 0;
    const bool writing = written < requests.size() && to_child_ >= 0;
    fds[n++] = {from_child_, POLLIN, 0};
    fds[n++] = {err_child_, POLLIN, 0};
    if (writing) fds[n++] = {to_child_, POLLOUT, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return "no answer within " + std::to_string(timeout_s_) + " s (timeout)";
    if (::poll(fds, n, static_cast<int>(std::min<long long>(left, 1000))) < 0 && errno != EINTR) {
      return std::string("poll failed: ") + std::strerror(errno);
    }
    if (writing && (fds[2].revents & (POLLOUT | POLLERR | POLLHUP))) {
      const ssize_t w = ::write(to_child_, requests.data() + written, requests.size() - written);
      if (w > 0) written += static_cast<std::size_t>(w);
      if (w < 0 && errno == EPIPE) close_fd(to_child_);  // it stopped reading; its answers tell why
    }
    if (fds[1].revents & (POLLIN | POLLHUP)) {
      const ssize_t r = ::read(err_child_, buf, sizeof buf);
      if (r > 0) {
        err_.append(buf, static_cast<std::size_t>(r));
        if (err_.size() > kStderrKept) err_.erase(0, err_.size() - kStderrKept);
      }
    }
    if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) {
      const ssize_t r = ::read(from_child_, buf, sizeof buf);
      if (r == 0) {  // the program closed its output: it ended
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
        // What it wrote to standard error before it ended.
        for (ssize_t e; (e = ::read(err_child_, buf, sizeof buf)) > 0;) err_.append(buf, static_cast<std::size_t>(e));
        if (err_.size() > kStderrKept) err_.erase(0, err_.size() - kStderrKept);
        return "the program ended (" + exit_text(status) + ") before it answered every sample of the batch";
      }
      if (r > 0) {
        pending_out_.append(buf, static_cast<std::size_t>(r));
        for (std::size_t nl; (nl = pending_out_.find('\n')) != std::string::npos;) {
          std::string line = pending_out_.substr(0, nl);
          pending_out_.erase(0, nl + 1);
          if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // blank lines are allowed
          lines.push_back(std::move(line));
          deadline = Clock::now() + std::chrono::duration<double>(timeout_s_);
        }
        if (lines.size() >= expected) return "";
      }
    }
  }
}

std::vector<Answer> ExternalProgram::evaluate(const std::vector<std::size_t>& ids, const std::vector<double>& inputs) {
  const std::size_t n = ids.size(), p = input_names_.size();
  std::vector<Answer> answers(n);
  if (pid_ < 0) start();
  std::string requests;
  std::map<std::size_t, std::size_t> row_of;
  for (std::size_t r = 0; r < n; ++r) {
    json in = json::object();
    for (std::size_t k = 0; k < p; ++k) in[input_names_[k]] = inputs[r * p + k];
    requests += json{{"sample", ids[r]}, {"inputs", in}}.dump() + "\n";
    row_of[ids[r]] = r;
  }
  std::vector<std::string> lines;
  std::string fault = exchange(requests, n, lines);
  std::vector<bool> answered(n, false);
  for (const std::string& line : lines) {
    json a;
    try {
      a = json::parse(line);
    } catch (const json::exception&) {
      fault = "the program wrote " + shown(line) + ", not a JSON line of the protocol";
      break;
    }
    const auto it = a.is_object() && a.contains("sample") && a["sample"].is_number_unsigned()
                        ? row_of.find(a["sample"].get<std::size_t>())
                        : row_of.end();
    if (it == row_of.end()) {
      fault = "the program wrote " + shown(line) + ", not the answer to a sample of the batch";
      break;
    }
    Answer& ans = answers[it->second];
    answered[it->second] = true;
    if (a.contains("failed")) {
      ans.failed = "the program: " + (a["failed"].is_string() ? a["failed"].get<std::string>() : a["failed"].dump());
      continue;
    }
    const json outs = a.value("outputs", json());
    for (const std::string& name : output_names_) {
      if (!outs.is_object() || !outs.contains(name) || !outs[name].is_number()) {
        ans.failed = "the program's answer " + shown(line) + " has no number for the output " + name;
        break;
      }
      ans.outputs.push_back(outs[name].get<double>());
    }
  }
  if (!fault.empty()) {
    const std::string why = fault + stderr_tail();
    stop(true);  // a new process for the next batch
    for (std::size_t r = 0; r < n; ++r) {
      if (!answered[r]) answers[r].failed = why;
    }
  }
  return answers;
}

}  // namespace poise::kinds::external
