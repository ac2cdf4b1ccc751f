// escapeControl and makeError: a name from outside, echoed in a one-line error, keeps the line whole and drives no terminal.
#include "core/text_escape.h"

#include <gtest/gtest.h>

#include <string>

#include "core/result.h"

namespace dentsim {
namespace {

TEST(TextEscape, ControlBytesBecomeHexAndUtf8Stays) {
  EXPECT_EQ(escapeControl("a\nb\x1b[31mc\x7f"), "a\\x0ab\\x1b[31mc\\x7f");
  EXPECT_EQ(escapeControl("z\xc3\xa4hne"), "z\xc3\xa4hne");               // a typed name keeps its UTF-8
  EXPECT_EQ(escapeControl("z\xc3\xa4", 200, true), "z\\xc3\\xa4");          // a binary token does not
  EXPECT_EQ(escapeControl("abcdef", 3), "abc...");
}

// A reader may escape a name before makeError escapes it again: the second pass changes nothing.
TEST(TextEscape, EscapingTwiceReadsAsOnce) {
  const std::string once = escapeControl("x\n\x1b]0;title\x07y");
  EXPECT_EQ(escapeControl(once), once);
}

// A path is shown whole, however long: the user must recognise it.
TEST(TextEscape, APathIsNeverShortened) {
  const std::string long_path(5000, 'p');
  EXPECT_EQ(shownPath(long_path), long_path);
  EXPECT_EQ(shownPath("a\tb"), "a\\x09b");
}

// makeError's `where` is a path as often as not: its newline and ESC come out escaped, so the
// message is one line with no raw escape byte.
TEST(TextEscape, MakeErrorEscapesWhere) {
  const Error e = makeError("dir/t\n\x1b[31m.stl", "cannot open: No such file or directory");
  EXPECT_EQ(e.message, "dir/t\\x0a\\x1b[31m.stl: cannot open: No such file or directory");
  EXPECT_EQ(makeError("", "plain").message, "plain");
}

}  // namespace
}  // namespace dentsim
