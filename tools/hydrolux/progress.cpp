#include "progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

namespace hydrolux::cli {

ProgressBar::ProgressBar(std::string job, bool quiet)
    : job_(std::move(job)), quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0), start_(Clock::now()),
      last_print_(start_) {}

ProgressFn ProgressBar::callback() {
  return [this](double fraction, std::string_view label) { update(fraction, label); };
}

void ProgressBar::update(double fraction, std::string_view label) {
  if (quiet_ || finished_) return;
  const auto now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  // Off a terminal, print a line only every 5 s, so logs stay short.
  const double interval = tty_ ? 0.1 : 5.0;
  if (std::chrono::duration<double>(now - last_print_).count() < interval && fraction < 1.0) return;
  last_print_ = now;
  const std::string eta =
      fraction > 0.02 ? fmt::format("{:.0f} s", elapsed * (1 - fraction) / fraction) : std::string("--");
  fmt::print(stderr, "{}[{}] {:3.0f}%  {:<32}  elapsed {:.1f} s  ETA {}{}", tty_ ? "\r\033[K" : "", job_,
             100 * fraction, label, elapsed, eta, tty_ ? "" : "\n");
  std::fflush(stderr);
  printed_ = true;
}

void ProgressBar::clear() {
  if (!quiet_ && !finished_ && tty_ && printed_) {
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
  }
}

void ProgressBar::finish() {
  if (quiet_ || finished_) return;
  finished_ = true;
  if (tty_ && printed_) fmt::print(stderr, "\n");
}

ProgressBar::~ProgressBar() { clear(); }

}  // namespace hydrolux::cli
