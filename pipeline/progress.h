// Progress of a long stage: an ETA from the recent cost per unit of work and load (simulated
// seconds times particles), with the load's recent growth carried forward, so that a scene that
// grows heavier (emitters) is not promised too early; on a terminal one updating line with a bar
// instead of a line per frame.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <deque>
#include <string>
#include <algorithm>
#include <utility>

#include <fmt/format.h>

namespace mf::pipeline {

class StageProgress {
 public:
  /// `total`: the work to do, in the unit `update` reports (e.g. simulated seconds).
  StageProgress(std::string stage, double start, double total, double load = 1)
      : stage_(std::move(stage)), start_(start), total_(total), tty_(isatty(STDERR_FILENO) == 1) {
    samples_.push_back({0.0, start, load});
  }

  bool terminal() const { return tty_; }

  /// Seconds left: the last few updates' (at most 8) wall time per unit of work and load, times
  /// the work left at the current load growing as it did over those updates (never shrinking).
  double eta() const {
    const Sample& a = samples_.front();
    const Sample& b = samples_.back();
    if (b.done <= a.done) return 0;
    const double work = b.done - a.done, cost = (b.wall - a.wall) / (work * 0.5 * (a.load + b.load));
    const double growth = std::max(0.0, (b.load - a.load) / work), left = total_ - b.done;
    return cost * (b.load * left + 0.5 * growth * left * left);
  }

  /// Records `done` (start .. total) at `load` and, on a terminal, redraws the line with `detail`.
  void update(double done, double load, const std::string& detail) {
    samples_.push_back({seconds(), done, load});
    if (samples_.size() > 9) samples_.pop_front();
    if (!tty_) return;
    const double share = total_ > start_ ? (done - start_) / (total_ - start_) : 1;
    const int width = 24, filled = int(share * width + 0.5);
    std::string bar(size_t(std::max(0, std::min(width, filled))), '#');
    bar.resize(size_t(width), '.');
    fmt::print(stderr, "\r[{} {}] {:3.0f}% {}  left ~{:.0f} s\033[K", stage_, bar, 100 * share, detail, eta());
    std::fflush(stderr);
  }

  /// Ends the terminal line (nothing otherwise).
  void finish() const {
    if (tty_) fmt::print(stderr, "\n");
  }

  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  std::string stage_;
  double start_, total_;
  bool tty_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  struct Sample {
    double wall, done, load;
  };
  std::deque<Sample> samples_;
};

}  // namespace mf::pipeline
