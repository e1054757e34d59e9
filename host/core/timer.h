#pragma once
/// Wall-clock timing of pipeline stages, reported as `timings` in report.json.
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace cutwork {

class Stopwatch {
 public:
  Stopwatch() : m_start(std::chrono::steady_clock::now()) {}
  /// Seconds since construction or the last restart().
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
  }
  void restart() { m_start = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point m_start;
};

/// Named durations in the order they were recorded; adding to an existing name accumulates.
class Timings {
 public:
  void add(const std::string& name, double seconds) {
    for (auto& [n, s] : m_entries)
      if (n == name) {
        s += seconds;
        return;
      }
    m_entries.emplace_back(name, seconds);
  }
  const std::vector<std::pair<std::string, double>>& entries() const { return m_entries; }

 private:
  std::vector<std::pair<std::string, double>> m_entries;
};

}  // namespace cutwork
