#pragma once
/// @file Text from input (names, descriptions, file names) made safe for POV-Ray 3.7 scene
/// language: comments, string literals and identifiers (and, for SVG, for XML). Every writer of SDL (instance scenes,
/// terrain scenes, palette includes) goes through these, so no input can end a comment, close
/// a string or declare anything.
///
/// Naming scheme of every identifier ifsforge writes: `IFS_<Kind>` or `IFS_<Kind>_<Name>`, where
/// Kind is a capitalised ASCII word chosen by ifsforge ("Palette", "Mesh", "Terrain") and Name
/// is the input name reduced to ASCII letters, digits and '_' (accents dropped: "Crème brûlée"
/// gives Creme_brulee). POV-Ray's reserved words are all lower case, so an identifier starting
/// with "IFS_" can never be one; a PovNames keeps the identifiers of one file unique.
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace ifsforge {

/// @brief UTF-8 `text` in printable ASCII: Latin letters lose their accents ("é" -> "e",
/// "ß" -> "ss", "Æ" -> "AE"), typographic quotes, dashes and spaces become their ASCII forms;
/// control characters become spaces; any other character, and each byte that is not valid
/// UTF-8, becomes `unknown`.
std::string ascii_text(const std::string& text, char unknown = '?');

/// @brief `text` made safe inside a `//` comment, on one line: ASCII (ascii_text), line breaks
/// become spaces, '#' becomes "No." and "/*", "*/" are broken up, so nothing can end the
/// comment or look like a directive.
std::string pov_comment(const std::string& text);
/// @brief One `// ...` line per line of `text` (pov_comment of each), each ending in '\n'.
std::string pov_comment_lines(const std::string& text);
/// @brief A POV-Ray string literal, quotes included: ASCII (ascii_text, control characters as
/// spaces), backslashes and quotes escaped. POV-Ray 3.7 warns about non-ASCII bytes in strings.
std::string pov_string(const std::string& text);

/// @brief The name part of an identifier: ascii_text of `name` with every run of characters
/// other than letters and digits turned into one '_', trimmed of '_' at both ends, at most 48
/// characters. Empty when nothing is left.
std::string pov_name(const std::string& name);
/// @brief "IFS_<kind>_<pov_name(name)>", or "IFS_<kind>" when the name part is empty. `kind`
/// must be a capitalised ASCII word ([A-Z][A-Za-z0-9]*), or std::invalid_argument.
std::string pov_identifier(const std::string& kind, const std::string& name);

/// @brief `text` as XML character data or attribute value (SVG): & < > " ' as entities,
/// control characters other than tab and line feed as spaces, bytes that are not valid UTF-8
/// (and U+FFFE, U+FFFF) as U+FFFD; other characters kept.
std::string xml_text(const std::string& text);

/// @brief POV-Ray 3.7's reserved words (keywords, directives, built-in identifiers), sorted.
/// All are lower case.
const std::vector<std::string_view>& pov_reserved_words();
bool pov_reserved_word(std::string_view word);

/// @brief The identifiers of one file: each new one is pov_identifier(kind, name), with "_2",
/// "_3", ... appended when that is already taken in this file.
class PovNames {
 public:
  /// `reserved`: identifiers the file already uses (its fixed names).
  explicit PovNames(std::vector<std::string> reserved = {});
  std::string take(const std::string& kind, const std::string& name);

 private:
  std::set<std::string> used_;
};

}  // namespace ifsforge
