#pragma once
// The one JSON reader of io/ (systems, terrain recipes, palette recipes): a document parsed from
// untrusted text with bounded nesting (nlohmann's dump, copy and comparison recurse, so a value
// nested 100,000 deep would overflow the stack), then typed access to its values that names the
// file and the JSON path of anything wrong ("file: /maps/2/matrix: expected 2 rows ...").
// Private to src/io: the only place nlohmann is included besides the writers.
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge::detail {

using nlohmann::json;

/// Deeper than any ifsforge document needs (nested super-IFS systems reach a handful of levels).
constexpr int kMaxJsonDepth = 100;

/// The document in `text`; InputError "source:line:col: ..." when it is not valid JSON or nests
/// deeper than kMaxJsonDepth.
json parse_json_document(const std::string& text, const std::string& source);

class JsonReader {
 public:
  explicit JsonReader(std::string source) : source_(std::move(source)) {}
  const std::string& source() const { return source_; }

  /// The document in `text` (see parse_json_document).
  json document(const std::string& text) const { return parse_json_document(text, source_); }
  /// The document, which must be an object with "format": `format`.
  json document(const std::string& text, const char* format) const;

  /// InputError "source: path: what" (path "/" for the document itself).
  [[noreturn]] void fail(const std::string& path, const std::string& what) const;
  /// A value's type and its text, cut to 40 characters, for messages.
  static std::string describe(const json& j);

  /// Fails on a non-object or on any member not in `known`; the message lists `known`, or says
  /// `hint` when one is given.
  void only(const json& j, const std::string& path, std::initializer_list<const char*> known,
            const char* hint = nullptr) const;

  double number(const json& j, const std::string& path) const;
  /// A whole number in lo..hi.
  int integer(const json& j, const std::string& path, int lo, int hi) const;
  /// A whole number >= 0.
  std::uint64_t seed(const json& j, const std::string& path) const;
  std::string text(const json& j, const std::string& path) const;
  /// An array of numbers of any length.
  std::vector<double> numbers(const json& j, const std::string& path) const;
  /// An array of exactly `count` numbers.
  std::vector<double> numbers(const json& j, const std::string& path, std::size_t count) const;
  /// `numbers`, each within +-kMaxCoefficient (a map's matrix row, offset or channel row).
  std::vector<double> coefficients(const json& j, const std::string& path, std::size_t count) const;
  /// One number for every component, or an array of `count`.
  std::vector<double> per_axis(const json& j, const std::string& path, std::size_t count) const;
  /// A non-empty array of rows of numbers, all rows as long as the first.
  std::vector<std::vector<double>> matrix(const json& j, const std::string& path) const;

  /// Runs `step` and re-throws its InputError at `path` (an error already naming this file, from a
  /// nested read, passes unchanged).
  template <typename Step>
  auto at(const std::string& path, Step step) const -> decltype(step()) {
    try {
      return step();
    } catch (const InputError& e) {
      if (std::string(e.what()).rfind(source_, 0) == 0) throw;
      fail(path, e.what());
    }
  }

 private:
  std::string source_;
};

}  // namespace ifsforge::detail
