#include "core/diagnostics.h"

#include <cstdio>
#include <mutex>
#include <set>
#include <utility>

namespace poise::diagnostics {
namespace {

std::mutex& sink_mutex() {
  static std::mutex m;
  return m;
}

Sink& current() {
  static Sink s;
  return s;
}

void emit(Kind kind, std::string_view text) {
  const std::lock_guard<std::mutex> lock(sink_mutex());
  if (current()) {
    current()(kind, text);
    return;
  }
  const std::string_view prefix = kind == Kind::kWarning ? "poise: warning: " : "";
  std::fprintf(stderr, "%.*s%.*s\n", static_cast<int>(prefix.size()), prefix.data(), static_cast<int>(text.size()),
               text.data());
}

}  // namespace

Sink set_sink(Sink sink) {
  const std::lock_guard<std::mutex> lock(sink_mutex());
  return std::exchange(current(), std::move(sink));
}

void warning(std::string_view text) { emit(Kind::kWarning, text); }

void warning_once(std::string_view text) {
  static std::mutex mutex;
  static std::set<std::string, std::less<>> shown;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (!shown.emplace(text).second) return;
  }
  emit(Kind::kWarning, text);
}

void progress(std::string_view text) { emit(Kind::kProgress, text); }

Capture::Capture() {
  previous_ = set_sink([this](Kind kind, std::string_view text) {
    (kind == Kind::kWarning ? warnings_ : progress_).append(text).append("\n");
  });
}

Capture::~Capture() { set_sink(std::move(previous_)); }

}  // namespace poise::diagnostics
