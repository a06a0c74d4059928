// The one error type of the core: its message is the user-facing one-line reason, and every
// front end (CLI, MeshLab, pymeshlab) prints it verbatim.
#pragma once

#include <stdexcept>
#include <string>

namespace sdp {

class ParameterizationError : public std::runtime_error {
 public:
  explicit ParameterizationError(const std::string& reason) : std::runtime_error(reason) {}
};

}  // namespace sdp
