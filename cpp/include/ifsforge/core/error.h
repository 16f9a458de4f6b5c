#pragma once
/// @file Exception types. Every error that reaches a user names what was wrong and where.
#include <stdexcept>
#include <string>

namespace ifsforge {

/// @brief Base of every ifsforge error.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// @brief Malformed input: a file, a parameter, a coefficient (NaN, wrong shape, ...).
class InputError : public Error {
 public:
  using Error::Error;
};

/// @brief The system has no attractor (neither hyperbolic nor contractive on average).
class DivergentSystemError : public InputError {
 public:
  using InputError::InputError;
};

/// @brief The job would need more memory than the budget allows; nothing was allocated.
class MemoryBudgetError : public Error {
 public:
  using Error::Error;
};

/// @brief A path could not be read or written.
class FileError : public Error {
 public:
  using Error::Error;
};

/// @brief The progress callback asked to stop.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

}  // namespace ifsforge
