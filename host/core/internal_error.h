#pragma once
/// A broken precondition inside cutwork: a bug, not bad input. Thrown where a caller in cutwork
/// passed what no user input can produce (sizes that disagree, a call out of order, an enum value
/// no branch handles). It is deliberately *not* a cutwork::Error (host/core/error.h): the command
/// line reports it as "internal error" with exit code 1, where errors a user can cause and fix
/// exit with code 2 (host/core/exit_status.h).
#include <stdexcept>

namespace cutwork {

class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

}  // namespace cutwork
