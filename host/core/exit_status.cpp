#include "host/core/exit_status.h"

#include <new>

#include "host/core/error.h"
#include "host/core/input_file.h"

namespace cutwork {

ExitStatus exit_status_for(std::exception_ptr e) {
  // One line, of bounded length, whatever a message quotes from the input.
  const auto line = [](const std::string& prefix, const char* what) { return prefix + excerpt(what, 2000); };
  try {
    std::rethrow_exception(e);
  } catch (const Interrupted& x) {
    return {128 + x.signal(), line("cutwork: ", x.what())};
  } catch (const Error& x) {
    return {2, line("cutwork: ", x.what())};
  } catch (const std::bad_alloc&) {
    return {2, "cutwork: out of memory (try a coarser mesh resolution)"};
  } catch (const std::exception& x) {
    // Anything else is a bug in cutwork, not bad input: say so, distinctly.
    return {1, line("cutwork: internal error: ", x.what())};
  } catch (...) {
    return {1, "cutwork: internal error: an exception that is not a std::exception"};
  }
}

}  // namespace cutwork
