#pragma once
/// @file Exception types. Every error that reaches a user names what was wrong and where.
#include <stdexcept>
#include <string>

namespace ifsforge {

/// @brief `text` with every byte that is not printable ASCII or part of valid UTF-8 written as
/// \xNN (NUL included), so a message quoting hostile input stays whole and readable.
std::string printable_text(const std::string& text);

/// @brief Base of every ifsforge error; its message is always printable (see printable_text).
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(printable_text(what)) {}
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
