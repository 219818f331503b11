#pragma once
// Errors carry their context as text and are caught once, at the CLI boundary,
// which maps them to exit codes: InputError -> 2, SolverError -> 1.
#include <stdexcept>
#include <string>

namespace rigidae {

// Bad input: a scene file or a command line that cannot be used as given.
// The message already names the file, line and column (or the option) and
// says what would be valid.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The integrator could not continue. Everything recorded so far stays on disk.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rigidae
