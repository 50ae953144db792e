#pragma once
/// One sink for what Poise tells a person while it works: warnings ("poise: warning: ...") and
/// progress lines. By default they go to stderr; the command line keeps that, a test or the
/// Python module can direct them elsewhere (set_sink), e.g. to collect the warnings of a run.
/// Thread-safe: lines from several threads arrive whole, one call of the sink at a time.
#include <functional>
#include <string>
#include <string_view>

namespace poise::diagnostics {

enum class Kind { kWarning, kProgress };

/// Receives each message without its "poise: warning: " prefix or trailing newline.
using Sink = std::function<void(Kind, std::string_view)>;

/// Directs every later message to `sink`; an empty sink restores stderr. Returns the previous
/// sink (empty if it was stderr), so a caller can restore it.
Sink set_sink(Sink sink);

/// "poise: warning: <text>" on stderr by default.
void warning(std::string_view text);
/// The same, at most once per process for one text (a study built several times in a run:
/// plan, run, report, says its warnings once).
void warning_once(std::string_view text);
/// A progress line as given (indentation kept), on stderr by default.
void progress(std::string_view text);

/// Collects the messages of its lifetime instead of printing them (for tests); restores the
/// previous sink when it goes.
class Capture {
 public:
  Capture();
  ~Capture();
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;
  const std::string& warnings() const { return warnings_; }  ///< one line each
  const std::string& progress() const { return progress_; }

 private:
  Sink previous_;
  std::string warnings_, progress_;
};

}  // namespace poise::diagnostics
