#pragma once
// Progress on stderr with elapsed time and an ETA, redrawn in place on a terminal and printed at
// most every few seconds otherwise (logs, CI).
#include <chrono>
#include <string>

#include "hydrolux/core/progress.hpp"

namespace hydrolux::cli {

class ProgressBar {
 public:
  ProgressBar(std::string job, bool quiet);
  // A bar left unfinished (an error was thrown) is erased from the terminal, so the error's one
  // line is not printed after it.
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  ProgressFn callback();
  void update(double fraction, std::string_view label);
  // Erases the bar from the terminal so that a warning line can be printed; the next update redraws it.
  void clear();
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string job_;
  bool quiet_, tty_;
  Clock::time_point start_, last_print_;
  bool printed_ = false, finished_ = false;
};

}  // namespace hydrolux::cli
