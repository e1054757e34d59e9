#pragma once
/// Deterministic random numbers for the pattern initialisations. std::mt19937_64 is fully
/// specified by the C++ standard, but the std:: distributions are not (their output differs
/// between standard libraries), so the conversions to doubles and ranges are done here: the
/// same seed gives the same layout bit for bit on every platform.
#include <cstdint>
#include <random>
#include <stdexcept>
#include <sstream>
#include <string>

namespace cutwork {

class PatternRng {
 public:
  explicit PatternRng(uint64_t seed) : m_engine(seed) {}
  /// Uniform in [0, 1): the top 53 bits of one 64-bit draw.
  double uniform() { return double(m_engine() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0.
  int below(int n) {
    const int k = int(uniform() * n);
    return k < n ? k : n - 1;
  }

  /// The engine's complete state as text (the standard's format: the same on every platform),
  /// for checkpoints; set_state() continues the sequence exactly. set_state throws
  /// std::invalid_argument for text that is not such a state.
  std::string state() const {
    std::ostringstream out;
    out << m_engine;
    return out.str();
  }
  void set_state(const std::string& state) {
    std::istringstream in(state);
    std::mt19937_64 engine;
    in >> engine;
    if (in.fail()) throw std::invalid_argument("not a random generator state");
    m_engine = engine;
  }

 private:
  std::mt19937_64 m_engine;
};

}  // namespace cutwork
