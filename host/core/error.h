#pragma once
/// Typed errors. Library code throws these with a message a user can act on; the command line
/// prints what() as one line on stderr and exits with code 2 (see host/cli).
#include <stdexcept>
#include <string>

namespace cutwork {

/// Base of every error cutwork reports to a user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input: an unreadable or invalid file, scene, value or selection.
/// The message names the file or JSON path and what is wrong.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A solve that cannot produce a valid result: an unconstrained (singular) model, zero or
/// non-finite loads, a load beyond the structure's capacity, Newton non-convergence.
class SolveError : public Error {
 public:
  using Error::Error;
};

/// A run stopped by SIGINT or SIGTERM at a point where it could stop cleanly; the command line
/// exits with 128 + the signal's number (130, 143) after the message.
class Interrupted : public Error {
 public:
  Interrupted(const std::string& message, int signal) : Error(message), m_signal(signal) {}
  int signal() const { return m_signal; }

 private:
  int m_signal;
};

/// A requested compute device (e.g. --device vulkan) is not available.
class DeviceError : public Error {
 public:
  using Error::Error;
};

}  // namespace cutwork
