#pragma once
/// @file The names of enumerated settings, written once per enum: a table of {value, name}
/// pairs beside the enum (a specialisation of EnumNames), read by name_of, parse_name and
/// names_of, so C++, the Python bindings and the CLI's choices share one spelling and one error.
#include <string>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge {

template <typename E>
struct NamedValue {
  E value;
  const char* name;
};

/// Specialised beside each enum E with `static constexpr const char* what` (the setting's name
/// in messages) and `static constexpr NamedValue<E> values[]` (every value once, the default
/// first where there is one).
template <typename E>
struct EnumNames;

/// The name of `value` ("?" for a value outside the table, which a valid enum never is).
template <typename E>
constexpr const char* name_of(E value) {
  for (const auto& v : EnumNames<E>::values)
    if (v.value == value) return v.name;
  return "?";
}

/// Every name of E, in table order (the CLI's choices).
template <typename E>
std::vector<std::string> names_of() {
  std::vector<std::string> out;
  for (const auto& v : EnumNames<E>::values) out.push_back(v.name);
  return out;
}

/// The value named `text`; InputError "unknown <what> 'text'; choose one of: a, b, c" otherwise.
template <typename E>
E parse_name(const std::string& text, const std::string& what = EnumNames<E>::what) {
  std::string list;
  for (const auto& v : EnumNames<E>::values) {
    if (text == v.name) return v.value;
    list += std::string(list.empty() ? "" : ", ") + v.name;
  }
  throw InputError("unknown " + what + " '" + text + "'; choose one of: " + list);
}

}  // namespace ifsforge
