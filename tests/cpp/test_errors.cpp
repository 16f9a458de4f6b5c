// Error messages stay printable and whole whatever bytes the input held.
#include <gtest/gtest.h>

#include "ifsforge/core/error.h"
#include "ifsforge/io/ifs_json.h"

namespace ifsforge {
namespace {

TEST(PrintableText, EscapesControlBytesNulAndInvalidUtf8) {
  EXPECT_EQ(printable_text(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable_text("\xff\xfe"), "\\xFF\\xFE");
  EXPECT_EQ(printable_text("\x1b[31m"), "\\x1B[31m");
  EXPECT_EQ(printable_text("\xed\xa0\x80"), "\\xED\\xA0\\x80");  // a UTF-16 surrogate
  EXPECT_EQ(printable_text("caf\xc3\xa9 \xe2\x82\xac\n"), "caf\xc3\xa9 \xe2\x82\xac\n");  // valid UTF-8 kept
  EXPECT_EQ(printable_text("\xc3"), "\\xC3");  // a truncated sequence
}

TEST(PrintableText, EveryErrorIsPrintable) {
  const InputError e(std::string("x\0y", 3));
  EXPECT_STREQ(e.what(), "x\\x00y");
}

TEST(JsonDepth, DeepNestingIsRefusedWithItsPlace) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  try {
    parse_ifs_json("{\n\"maps\": " + deep + "}", "deep.json");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    // "{" is level 1; the k-th "[" (column 8 + k) opens level k + 1, so level 101 is column 108.
    EXPECT_EQ(std::string(e.what()).rfind("deep.json:2:108: ", 0), 0u) << e.what();
  }
}

TEST(JsonDepth, BracketsInsideStringsDoNotCount) {
  const std::string text = "{\"name\": \"" + std::string(500, '[') + "\", \"maps\": [{\"matrix\": [[0.5, 0], [0, 0.5]], "
                           "\"offset\": [0, 0]}, {\"matrix\": [[0.5, 0], [0, 0.5]], \"offset\": [1, 0]}]}";
  EXPECT_EQ(parse_ifs_json(text, "ok.json").size(), 2u);
}

}  // namespace
}  // namespace ifsforge
