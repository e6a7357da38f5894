// One error model for the whole core (ENGINEERING.md, habit 4).
//   InvalidArgument -> Python ValueError: a caller passed something outside its
//                      documented range; the message names the argument and limit.
//   GeometryError   -> Python RuntimeError: the input was well-formed but the
//                      geometry defeated us (degenerate face, OpenCASCADE failure,
//                      recursion guard hit). The message names the face.
//   Cancelled       -> raised when Progress::cancel was set; nothing is returned.
#pragma once

#include <stdexcept>
#include <string>

namespace isocam {

class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class GeometryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("computation cancelled") {}
};

}  // namespace isocam
