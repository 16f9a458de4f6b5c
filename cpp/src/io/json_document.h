#pragma once
// Parsing a JSON document from untrusted text: nesting is bounded before the DOM is built
// (nlohmann's dump, copy and comparison recurse, so a value nested 100,000 deep would overflow
// the stack), and every syntax error names the file and line:column.
#include <nlohmann/json.hpp>
#include <string>

namespace ifsforge::detail {

/// Deeper than any ifsforge document needs (nested super-IFS systems reach a handful of levels).
constexpr int kMaxJsonDepth = 100;

/// The document in `text`; InputError "source:line:col: ..." when it is not valid JSON or nests
/// deeper than kMaxJsonDepth.
nlohmann::json parse_json_document(const std::string& text, const std::string& source);

}  // namespace ifsforge::detail
