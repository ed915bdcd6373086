// Error kinds shared by every tool. Each tool's main catches them once and maps
// them to exit codes (tools/tool_main.h): InputError -> 2, anything else -> 1.
#pragma once

#include <stdexcept>

namespace aal {

// Bad usage or bad input data: wrong arguments, missing/corrupt/mismatched
// files. The message names the offending file or value and what is wrong.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace aal
