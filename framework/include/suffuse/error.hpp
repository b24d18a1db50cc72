#pragma once
#include <stdexcept>
#include <string>

namespace suffuse {

// Every error the framework reports to a user. The message is complete:
// callers print what() as is.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace suffuse
