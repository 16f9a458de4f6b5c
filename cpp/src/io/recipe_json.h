#pragma once
// Reading the terrain and palette recipes: typed access to JSON values that names the file and
// the JSON path of anything wrong (the same style as the ifsforge/1 reader).
#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "json_document.h"
#include "ifsforge/core/error.h"

namespace ifsforge::detail {

using nlohmann::json;

class RecipeReader {
 public:
  explicit RecipeReader(std::string source) : source_(std::move(source)) {}
  const std::string& source() const { return source_; }

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw InputError(source_ + ": " + (path.empty() ? "/" : path) + ": " + what);
  }

  static std::string describe(const json& j) {
    std::string s = j.dump();
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return std::string(j.type_name()) + " " + s;
  }

  /// Fails on any member not in `known`.
  void only(const json& j, const std::string& path, std::initializer_list<const char*> known) const {
    if (!j.is_object()) fail(path, "expected an object, found " + describe(j));
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool ok = false;
      for (const char* k : known) ok |= it.key() == k;
      if (!ok) {
        std::string list;
        for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + k;
        fail(path + "/" + it.key(), "unknown field (expected one of: " + list + ")");
      }
    }
  }

  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number, found " + describe(j));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "the number is not finite");
    return v;
  }

  int integer(const json& j, const std::string& path, int lo, int hi) const {
    const double v = number(j, path);
    if (v != std::floor(v) || v < lo || v > hi)
      fail(path, "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", found " +
                     describe(j));
    return int(v);
  }

  std::uint64_t seed(const json& j, const std::string& path) const {
    if (!j.is_number_unsigned() && !(j.is_number_integer() && j.get<long long>() >= 0))
      fail(path, "expected a seed (a whole number >= 0), found " + describe(j));
    return j.get<std::uint64_t>();
  }

  std::string text(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string, found " + describe(j));
    return j.get<std::string>();
  }

  std::vector<double> numbers(const json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, "expected an array of numbers, found " + describe(j));
    std::vector<double> out;
    for (std::size_t i = 0; i < j.size(); ++i) out.push_back(number(j[i], path + "/" + std::to_string(i)));
    return out;
  }

  std::vector<double> numbers(const json& j, const std::string& path, std::size_t count) const {
    std::vector<double> out = numbers(j, path);
    if (out.size() != count)
      fail(path, "expected " + std::to_string(count) + " numbers, found " + std::to_string(out.size()));
    return out;
  }

  std::vector<std::vector<double>> matrix(const json& j, const std::string& path) const {
    if (!j.is_array() || j.empty()) fail(path, "expected an array of rows, found " + describe(j));
    std::vector<std::vector<double>> out;
    for (std::size_t r = 0; r < j.size(); ++r) {
      out.push_back(numbers(j[r], path + "/" + std::to_string(r)));
      if (out.back().size() != out.front().size())
        fail(path + "/" + std::to_string(r), "row " + std::to_string(r) + " has " + std::to_string(out.back().size()) +
                                                 " values, row 0 has " + std::to_string(out.front().size()));
    }
    return out;
  }

  /// The document, after checking "format".
  json parse(const std::string& text, const char* format) const {
    const json j = parse_json_document(text, source_);
    if (!j.is_object()) fail("", "expected a JSON object, found " + describe(j));
    if (!j.contains("format")) fail("/format", std::string("missing: this file needs \"format\": \"") + format + "\"");
    if (text_of(j["format"]) != format)
      fail("/format", std::string("expected \"") + format + "\", found " + describe(j["format"]));
    return j;
  }

 private:
  static std::string text_of(const json& j) { return j.is_string() ? j.get<std::string>() : std::string(); }
  std::string source_;
};

}  // namespace ifsforge::detail
