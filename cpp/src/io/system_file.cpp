#include "ifsforge/io/system_file.h"

#include "ifsforge/core/error.h"
#include "ifsforge/io/fractint.h"
#include "ifsforge/io/ifs_json.h"

namespace ifsforge {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Ifs load_system(const std::string& spec) {
  // "file.ifs:entry" names an entry; a plain path names a file.
  std::string path = spec, entry;
  const std::size_t colon = spec.rfind(':');
  if (colon != std::string::npos && !ends_with(spec, ".ifs") && !ends_with(spec, ".json") &&
      (ends_with(spec.substr(0, colon), ".ifs") || ends_with(spec.substr(0, colon), ".IFS"))) {
    path = spec.substr(0, colon);
    entry = spec.substr(colon + 1);
  }
  if (ends_with(path, ".ifs") || ends_with(path, ".IFS")) {
    std::vector<Ifs> systems = read_fractint(path);
    if (entry.empty()) return systems.front();
    std::string names;
    for (auto& s : systems) {
      if (s.name() == entry) return s;
      names += (names.empty() ? "" : ", ") + s.name();
    }
    throw InputError("'" + path + "' has no entry '" + entry + "'; it has: " + names);
  }
  return read_ifs_json(path);
}

}  // namespace ifsforge
