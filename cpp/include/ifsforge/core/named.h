#pragma once
/// @file Finding an entry of a registry by its name or an alias.
#include <string>

#include "ifsforge/core/error.h"

namespace ifsforge {

/// @brief The entry of `entries` (each with `renderer->name()` and `aliases`) called `name`;
/// InputError lists the choices, naming them `what`.
template <typename Entries>
const auto& find_named(const Entries& entries, const std::string& name, const std::string& what) {
  std::string known;
  for (const auto& entry : entries) {
    if (entry.renderer->name() == name) return *entry.renderer;
    for (const auto& alias : entry.aliases)
      if (alias == name) return *entry.renderer;
    known += (known.empty() ? "" : ", ") + entry.renderer->name();
  }
  throw InputError("unknown " + what + " '" + name + "'; choose one of: " + known);
}

}  // namespace ifsforge
