// The SDL sanitiser (io/pov_text.h): comments, strings and identifiers from hostile input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "ifsforge/io/pov_text.h"
#include "ifsforge/io/pov_palette.h"
#include "ifsforge/texture/palette.h"

namespace ifsforge {
namespace {

bool printable_ascii(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return c >= 0x20 && c < 0x7F; });
}

bool identifier_shape(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

const char* const kHostile[] = {"ok\n#declare Evil=1;\n//", "a */ b /* c", "#include \"x.inc\"", "say \"hi\" \\ \\\"",
                                "Cr\xc3\xa8me br\xc3\xbbl\xc3\xa9" "e", "sphere", "union", "pi", "1st", "", "\xff\xfe\x80",
                                "tab\tcr\r\x7f", "\xe2\x80\x9cquoted\xe2\x80\x9d \xe2\x80\x94 dash", "\xf0\x9f\x8c\xbf leaf"};

TEST(PovText, AsciiTextDropsAccentsAndReplacesTheRest) {
  EXPECT_EQ(ascii_text("Cr\xc3\xa8me br\xc3\xbbl\xc3\xa9" "e"), "Creme brulee");
  EXPECT_EQ(ascii_text("Stra\xc3\x9f" "e \xc3\x86on \xc5\x92uvre \xc5\x81\xc3\xb3" "d\xc5\xba"), "Strasse AEon OEuvre Lodz");
  EXPECT_EQ(ascii_text("\xe2\x80\x9cq\xe2\x80\x9d \xe2\x80\x94 \xe2\x80\x99"), "\"q\" - '");
  EXPECT_EQ(ascii_text("a\xf0\x9f\x8c\xbf" "b"), "a?b");             // one code point, one '?'
  EXPECT_EQ(ascii_text("\xff\xc3(\xe2\x82", '_'), "__(__");          // invalid bytes, one each
  EXPECT_EQ(ascii_text("\xc0\xaf\xed\xa0\x80"), "?????");             // overlong and surrogate forms
  EXPECT_EQ(ascii_text("a\nb\tc\x7f"), "a b c ");
  EXPECT_EQ(ascii_text("7\xc3\x97" "8\xc3\xb7" "2"), "7x8?2");
}

TEST(PovText, CommentsStayOneInertLine) {
  EXPECT_EQ(pov_comment("ok\n#declare Evil=1;\n//"), "ok No.declare Evil=1; //");
  EXPECT_EQ(pov_comment("x /* y */ z"), "x / * y * / z");
  EXPECT_EQ(pov_comment("**/"), "** /");
  for (const char* text : kHostile) {
    const std::string c = pov_comment(text);
    EXPECT_TRUE(printable_ascii(c)) << c;
    EXPECT_EQ(c.find('#'), std::string::npos) << c;
    EXPECT_EQ(c.find("*/"), std::string::npos) << c;
    EXPECT_EQ(c.find("/*"), std::string::npos) << c;
  }
  EXPECT_EQ(pov_comment_lines("first\nsecond #2\n"), "// first\n// second No.2\n");
  EXPECT_EQ(pov_comment_lines(""), "");
}

TEST(PovText, StringsCloseOnlyAtTheirEnd) {
  EXPECT_EQ(pov_string("\"; #system \"rm"), "\"\\\"; #system \\\"rm\"");
  EXPECT_EQ(pov_string("back\\slash\nCr\xc3\xa8me"), "\"back\\\\slash Creme\"");
  for (const char* text : kHostile) {
    const std::string s = pov_string(text);
    ASSERT_GE(s.size(), 2u);
    EXPECT_TRUE(printable_ascii(s)) << s;
    // Inside the quotes every '"' is escaped, and every backslash starts an escape pair.
    for (std::size_t i = 1; i + 1 < s.size(); ++i) {
      if (s[i] == '\\') {
        ASSERT_TRUE(s[i + 1] == '\\' || s[i + 1] == '"') << s;
        ++i;
      } else {
        ASSERT_NE(s[i], '"') << s;
      }
    }
  }
}

TEST(PovText, IdentifiersFollowTheNamingScheme) {
  EXPECT_EQ(pov_identifier("Palette", "ember lightness"), "IFS_Palette_ember_lightness");
  EXPECT_EQ(pov_identifier("Palette", "Cr\xc3\xa8me br\xc3\xbbl\xc3\xa9" "e"), "IFS_Palette_Creme_brulee");
  EXPECT_EQ(pov_identifier("Mesh", "my fern #1"), "IFS_Mesh_my_fern_1");
  EXPECT_EQ(pov_identifier("Palette", "1st"), "IFS_Palette_1st");
  EXPECT_EQ(pov_identifier("Palette", "sphere"), "IFS_Palette_sphere");
  EXPECT_EQ(pov_identifier("Palette", ""), "IFS_Palette");
  EXPECT_EQ(pov_identifier("Palette", "__ -- !!"), "IFS_Palette");
  EXPECT_EQ(pov_name(std::string(200, 'a')).size(), 48u);
  for (const char* text : kHostile) {
    const std::string id = pov_identifier("Palette", text);
    EXPECT_TRUE(identifier_shape(id)) << id;
    EXPECT_FALSE(pov_reserved_word(id)) << id;
  }
  EXPECT_THROW(pov_identifier("palette", "x"), std::invalid_argument);  // a lower-case kind could be a keyword
  EXPECT_THROW(pov_identifier("Pal_ette", "x"), std::invalid_argument);
  EXPECT_THROW(pov_identifier("", "x"), std::invalid_argument);
}

TEST(PovText, ReservedWordsAreLowerCaseSoTheSchemeAvoidsThem) {
  const auto& words = pov_reserved_words();
  EXPECT_GT(words.size(), 400u);
  EXPECT_TRUE(std::is_sorted(words.begin(), words.end()));
  EXPECT_EQ(std::adjacent_find(words.begin(), words.end()), words.end());
  for (const auto word : words)
    for (const char c : word) EXPECT_FALSE(c >= 'A' && c <= 'Z') << word;  // so no "IFS_..." is one
  for (const char* word : {"sphere", "union", "pi", "x", "declare", "mesh2", "srgb", "assumed_gamma", "tau"})
    EXPECT_TRUE(pov_reserved_word(word)) << word;
  EXPECT_FALSE(pov_reserved_word("IFS_Palette_sphere"));
  EXPECT_FALSE(pov_reserved_word("Sphere"));
}

TEST(PovText, NamesAreUniqueInAFile) {
  PovNames names;
  EXPECT_EQ(names.take("Mesh", "Cr\xc3\xa8me br\xc3\xbbl\xc3\xa9" "e"), "IFS_Mesh_Creme_brulee");
  EXPECT_EQ(names.take("Mesh", "Creme-brulee"), "IFS_Mesh_Creme_brulee_2");
  EXPECT_EQ(names.take("Mesh", "Creme_brulee_2"), "IFS_Mesh_Creme_brulee_2_2");
  EXPECT_EQ(names.take("Mesh", "creme brulee"), "IFS_Mesh_creme_brulee");
  EXPECT_EQ(names.take("Palette", "Creme brulee"), "IFS_Palette_Creme_brulee");
  PovNames taken({"IFS_Mesh"});
  EXPECT_EQ(taken.take("Mesh", ""), "IFS_Mesh_2");
}

TEST(PovText, XmlTextIsWellFormed) {
  EXPECT_EQ(xml_text("a<b>&\"c\"'"), "a&lt;b&gt;&amp;&quot;c&quot;&apos;");
  EXPECT_EQ(xml_text("Cr\xc3\xa8me\x01\n"), "Cr\xc3\xa8me \n");
  EXPECT_EQ(xml_text("x\xff" "y\xef\xbf\xbe"), "x\xef\xbf\xbdy\xef\xbf\xbd");
  EXPECT_EQ(xml_text("]]></title><script>"), "]]&gt;&lt;/title&gt;&lt;script&gt;");
}

TEST(PovText, PaletteIncludeDeclaresOnlyItsColorMap) {
  Palette palette;
  palette.colors = {{0.5f, 0.5f, 0.5f}, {1.0f, 0.0f, 0.04045f}};
  const std::string text = pov_palette_include(palette, "ok\n#declare Evil=1;\n// */", "desc\n#include \"x\"");
  std::size_t start = 0;
  int directives = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.rfind("//", 0) == 0) {
      EXPECT_EQ(line.find('#'), std::string::npos) << line;
      EXPECT_EQ(line.find("*/"), std::string::npos) << line;
    } else if (line.rfind("#", 0) == 0) {
      ++directives;
      EXPECT_EQ(line, "#declare IFS_Palette_ok_declare_Evil_1 = color_map {");
    }
  }
  EXPECT_EQ(directives, 1);
  // Linear rgb: sRGB 0.5 decodes to 0.2140411, 0.04045 to 0.04045 / 12.92.
  EXPECT_NE(text.find("  [0.000000 rgb <0.2140411, 0.2140411, 0.2140411>]\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  [1.000000 rgb <1.0000000, 0.0000000, 0.0031308>]\n"), std::string::npos) << text;
  EXPECT_NE(pov_color_map(palette).find("  [0.000000 srgb <0.500000, 0.500000, 0.500000>]"), std::string::npos);
}

}  // namespace
}  // namespace ifsforge
