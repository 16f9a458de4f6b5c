#include "json_document.h"

#include "ifsforge/core/error.h"

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

}  // namespace ifsforge::detail
