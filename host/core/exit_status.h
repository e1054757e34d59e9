#pragma once
/// How the command line ends on an exception: the one line it prints on stderr and its exit code.
///   cutwork::Error (InputError, SolveError, DeviceError)   2   the message; the user can fix it
///   cutwork::Interrupted (SIGINT, SIGTERM)                 128 + signal
///   std::bad_alloc                                         2   out of memory
///   anything else (InternalError, std::logic_error, …)     1   "internal error: …", a bug in cutwork
/// (CLI usage errors are CLI11's and exit 2 in host/cli/main.cpp.)
#include <exception>
#include <string>

namespace cutwork {

struct ExitStatus {
  int code = 0;
  std::string line;  ///< "cutwork: …", one line of bounded length, without the newline
};

/// The exit status for the exception `e` (not null).
ExitStatus exit_status_for(std::exception_ptr e);

}  // namespace cutwork
