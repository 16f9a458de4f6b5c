#include "json_reader.h"

#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/model/affine_map.h"

namespace ifsforge::detail {
namespace {

std::string place(const std::string& text, std::size_t offset, const std::string& source) {
  int line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return source + ":" + std::to_string(line) + ":" + std::to_string(column);
}

/// Throws at the first bracket opening level kMaxJsonDepth + 1 (brackets inside strings skipped).
void check_depth(const std::string& text, const std::string& source) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw InputError(place(text, i, source) + ": malformed JSON: arrays and objects nested deeper than " +
                         std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

}  // namespace

nlohmann::json parse_json_document(const std::string& text, const std::string& source) {
  check_depth(text, source);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::out_of_range& e) {
    const std::string what = e.what();
    throw InputError(source + ": a number is out of range: " + what.substr(what.find(']') + 2));
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is 1-based: the byte after the one that failed.
    const std::string what = e.what();
    const auto colon = what.rfind(": ");
    throw InputError(place(text, e.byte == 0 ? 0 : e.byte - 1, source) + ": malformed JSON: " +
                     (colon == std::string::npos ? what : what.substr(colon + 2)));
  }
}

json JsonReader::document(const std::string& text, const char* format) const {
  const json j = document(text);
  if (!j.is_object()) fail("", "expected a JSON object, found " + describe(j));
  if (!j.contains("format")) fail("/format", std::string("missing: this file needs \"format\": \"") + format + "\"");
  if (!j["format"].is_string() || j["format"].get<std::string>() != format)
    fail("/format", std::string("expected \"") + format + "\", found " + describe(j["format"]));
  return j;
}

void JsonReader::fail(const std::string& path, const std::string& what) const {
  throw InputError(source_ + ": " + (path.empty() ? "/" : path) + ": " + what);
}

std::string JsonReader::describe(const json& j) {
  std::string s = j.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return std::string(j.type_name()) + " " + s;
}

void JsonReader::only(const json& j, const std::string& path, std::initializer_list<const char*> known,
                      const char* hint) const {
  if (!j.is_object()) fail(path, "expected an object, found " + describe(j));
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool ok = false;
    for (const char* k : known) ok |= it.key() == k;
    if (ok) continue;
    std::string list;
    for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + k;
    fail(path + "/" + it.key(), "unknown field (" + (hint ? std::string(hint) : "expected one of: " + list) + ")");
  }
}

double JsonReader::number(const json& j, const std::string& path) const {
  if (!j.is_number()) fail(path, "expected a number, found " + describe(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(path, "the number is not finite");
  return v;
}

int JsonReader::integer(const json& j, const std::string& path, int lo, int hi) const {
  const double v = number(j, path);
  if (v != std::floor(v) || v < lo || v > hi)
    fail(path, "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", found " +
                   describe(j));
  return int(v);
}

std::uint64_t JsonReader::seed(const json& j, const std::string& path) const {
  if (!j.is_number_unsigned() && !(j.is_number_integer() && j.get<long long>() >= 0))
    fail(path, "expected a seed (a whole number >= 0), found " + describe(j));
  return j.get<std::uint64_t>();
}

std::string JsonReader::text(const json& j, const std::string& path) const {
  if (!j.is_string()) fail(path, "expected a string, found " + describe(j));
  return j.get<std::string>();
}

std::vector<double> JsonReader::numbers(const json& j, const std::string& path) const {
  if (!j.is_array()) fail(path, "expected an array of numbers, found " + describe(j));
  std::vector<double> out;
  for (std::size_t i = 0; i < j.size(); ++i) out.push_back(number(j[i], path + "/" + std::to_string(i)));
  return out;
}

std::vector<double> JsonReader::numbers(const json& j, const std::string& path, std::size_t count) const {
  if (!j.is_array()) fail(path, "expected an array of " + std::to_string(count) + " numbers, found " + describe(j));
  if (j.size() != count) fail(path, "expected " + std::to_string(count) + " numbers, found " + std::to_string(j.size()));
  return numbers(j, path);
}

std::vector<double> JsonReader::coefficients(const json& j, const std::string& path, std::size_t count) const {
  std::vector<double> out = numbers(j, path, count);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (std::fabs(out[i]) > kMaxCoefficient)
      fail(path + "/" + std::to_string(i), "a map coefficient must lie within +-1e9 (iterating it would "
                                           "escape to infinity), found " + describe(j[i]));
  return out;
}

std::vector<double> JsonReader::per_axis(const json& j, const std::string& path, std::size_t count) const {
  if (j.is_number()) return std::vector<double>(count, number(j, path));
  return numbers(j, path, count);
}

std::vector<std::vector<double>> JsonReader::matrix(const json& j, const std::string& path) const {
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

}  // namespace ifsforge::detail
