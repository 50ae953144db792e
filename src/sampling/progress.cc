#include "sampling/progress.h"

#include <unistd.h>

#include <cmath>

#include "core/format.h"

namespace poise::sampling {
namespace {
std::string hms(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{:02}:{:02}", s / 60, s % 60);
}
}  // namespace

Progress::Progress(std::string label, std::size_t total, bool enabled, std::FILE* out)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      out_(out),
      tty_(isatty(fileno(out)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::update(std::size_t done) {
  if (!enabled_ || total_ == 0) return;
  const auto now = std::chrono::steady_clock::now();
  const double t = elapsed_seconds();
  const double rate = t > 0 ? static_cast<double>(done) / t : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total_ - done) / rate : NAN;
  const double pct = 100.0 * static_cast<double>(done) / static_cast<double>(total_);
  if (tty_) {
    if (done != total_ && now - last_print_ < std::chrono::milliseconds(200)) return;
    last_print_ = now;
    std::fprintf(out_, "\r  %5.1f%%  %zu/%zu %s  %.0f %s/s  elapsed %s  ETA %s   ", pct, done, total_, label_.c_str(),
                 rate, label_.c_str(), hms(t).c_str(), hms(eta).c_str());
    std::fflush(out_);
  } else {
    const int decile = static_cast<int>(10 * done / total_);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(out_, "  %3d%%  %zu/%zu %s  %.0f %s/s  elapsed %s  ETA %s\n", decile * 10, done, total_,
                 label_.c_str(), rate, label_.c_str(), hms(t).c_str(), hms(eta).c_str());
  }
}

void Progress::finish() {
  if (!enabled_) return;
  if (tty_) std::fprintf(out_, "\n");
  std::fprintf(out_, "  done: %zu %s in %.2f s\n", total_, label_.c_str(), elapsed_seconds());
}

}  // namespace poise::sampling
