#pragma once
// Run progress on the console: a redrawn bar with steps/s and ETA on a terminal, plain periodic
// lines otherwise (log files, CI), so a long run is never silent.
#include "tsuchi/run/simulation.hpp"

#include <chrono>
#include <cstdio>
#include <string>

namespace tsuchi::app {

class ProgressReporter {
 public:
  explicit ProgressReporter(std::FILE* out);
  void update(const Progress& p);
  void finish(const Progress& p);
  // A line of its own between the progress updates (on a terminal, the bar's line is cleared first).
  void note(const std::string& line);

 private:
  void print(const Progress& p, bool final);

  std::FILE* out_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_;
  double last_reported_fraction_ = 0.0;
  bool started_ = false;
  std::int64_t start_step_ = 0;   // the step count at start_ (a later stage's start)
  double start_fraction_ = 0.0;  // where the run was at its first step (a restart starts on the way)
  Progress latest_;
};

}  // namespace tsuchi::app
