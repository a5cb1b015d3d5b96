// The error every reader throws for bad input (a missing or malformed file, NaN or Inf, an empty
// cloud): the message names the file (or the cloud's label) and what is wrong; the command line
// prints it and exits 2. Here, below the golden model, so its cloud checks throw it too.
#pragma once

#include <stdexcept>

namespace tigris {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tigris
