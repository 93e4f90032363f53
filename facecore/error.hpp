#pragma once
// The error every stage raises for bad input: a file, device or argument that is not what
// rostro expects. The command-line program turns it into one line and exit code 1.

#include <stdexcept>
#include <string>

namespace rostro {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "path:line: what" (line 0 leaves the line out), the shape every parser reports in.
std::string where(const std::string& path, long line, const std::string& what);

}  // namespace rostro
