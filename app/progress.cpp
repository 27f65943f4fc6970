#include "progress.hpp"

#include "console.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <unistd.h>

namespace tsuchi::app {

namespace {
std::string clock_text(double seconds) {
  if (!(seconds >= 0.0) || seconds > 1e7) return "--:--:--";
  const auto s = static_cast<long>(seconds + 0.5);
  return fmt::format("{}:{:02d}:{:02d}", s / 3600, (s / 60) % 60, s % 60);
}
}  // namespace

ProgressReporter::ProgressReporter(std::FILE* out)
    : out_(out), tty_(::isatty(::fileno(out)) != 0), start_(std::chrono::steady_clock::now()), last_(start_) {}

void ProgressReporter::update(const Progress& p) {
  // Each stage of a staged run is its own 0-100 %: its ETA is measured from its own start.
  if (!started_ || p.stage != latest_.stage) {
    if (started_) start_ = std::chrono::steady_clock::now(), start_step_ = p.step;
    started_ = true, start_fraction_ = p.fraction, last_reported_fraction_ = p.fraction;
  }
  latest_ = p;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_).count();
  const double fraction = p.fraction;
  // A terminal is redrawn 5 times a second; a log gets a line every 10 % or every 30 s.
  const bool due = tty_ ? since > 0.2 : (fraction >= last_reported_fraction_ + 0.1 || since > 30.0);
  if (!due) return;
  last_ = now;
  if (!tty_) last_reported_fraction_ = std::min(1.0, fraction);
  print(p, false);
}

void ProgressReporter::finish(const Progress& p) {
  print(p, true);
  if (tty_) std::fputc('\n', out_);
  std::fflush(out_);
}

void ProgressReporter::note(const std::string& line) {
  say(out_, "{}{}\n", tty_ ? "\r\x1b[K" : "", line);
  std::fflush(out_);
}

void ProgressReporter::print(const Progress& p, bool final) {
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = std::clamp(p.fraction, 0.0, 1.0);
  const double steps_per_s = wall > 0 ? static_cast<double>(p.step - start_step_) / wall : 0.0;
  // Measured from this run's start: a restart's progress so far says nothing of its speed.
  const double done = fraction - start_fraction_;
  const double eta = done > 0 ? wall * (1.0 - fraction) / done : -1.0;
  // When a recorder will stop the run before time.end, its value against its bound is the progress.
  const std::string measure = p.leader.empty()
                                  ? (std::isfinite(p.end_time) ? fmt::format("t={:.4g}/{:.4g} s", p.time, p.end_time)
                                                               : fmt::format("t={:.4g} s", p.time))
                                  : fmt::format("{}={:.4g}/{:.4g} t={:.4g} s", p.leader, p.leader_value,
                                                p.leader_bound, p.time);
  const std::string stage = p.stages > 1 ? fmt::format("stage {}/{} {} ", p.stage, p.stages, p.stage_name) : std::string{};
  const std::string status = fmt::format("{}{:5.1f}% step {} {} dt={:.3g} s {:.0f} steps/s {} {}", stage, 100.0 * fraction,
                                         p.step, measure, p.dt, steps_per_s, final ? "elapsed" : "ETA",
                                         clock_text(final ? wall : eta));
  if (tty_) {
    constexpr int width = 24;
    const int filled = static_cast<int>(fraction * width);
    say(out_, "\r[{}{}] {}\x1b[K", std::string(filled, '#'), std::string(width - filled, '.'), status);
  } else {
    say(out_, "{}\n", status);
  }
  std::fflush(out_);
}

}  // namespace tsuchi::app
