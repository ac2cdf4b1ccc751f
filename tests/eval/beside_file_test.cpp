// Tests of resolveBeside and liesWithin: a header's path stays in its file's folder, by name, by "..", by link and by a look-alike prefix.
#include "eval/beside_file.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;

TEST(BesideFile, AFileBesideOrBelowResolvesAgainstTheOwnersFolder) {
  test::TempDir dir;
  const std::string owner = dir.file("s.dses");
  auto beside = resolveBeside(owner, "initial.dvol", "tooth.file");
  ASSERT_TRUE(beside.ok()) << beside.message();
  EXPECT_EQ(*beside, dir.file("initial.dvol"));
  // Below it, and a ".." that stays inside, are fine; the file need not exist yet.
  EXPECT_TRUE(resolveBeside(owner, "teeth/a.dvol", "tooth.file").ok());
  EXPECT_TRUE(resolveBeside(owner, "teeth/../a.dvol", "tooth.file").ok());
}

TEST(BesideFile, AbsolutePathsAndClimbsOutAreRefusedNamingTheField) {
  test::TempDir dir;
  const std::string owner = dir.file("sub/s.dses");
  fs::create_directories(dir.file("sub"));
  auto absolute = resolveBeside(owner, "/etc/passwd", "tooth.file");
  ASSERT_FALSE(absolute.ok());
  EXPECT_NE(absolute.message().find(owner + ": tooth.file names \"/etc/passwd\""), std::string::npos) << absolute.message();
  EXPECT_NE(absolute.message().find("absolute path"), std::string::npos) << absolute.message();
  for (const char* climb : {"../x.dvol", "../../../../etc/passwd", "a/../../x.dvol"}) {
    auto r = resolveBeside(owner, climb, "task");
    ASSERT_FALSE(r.ok()) << climb;
    EXPECT_NE(r.message().find("lies outside it"), std::string::npos) << r.message();
  }
  // Control characters in a hostile header are not passed to the terminal.
  auto escape = resolveBeside(owner, "/x\x1b[2J", "task");
  ASSERT_FALSE(escape.ok());
  EXPECT_EQ(escape.message().find('\x1b'), std::string::npos);
  EXPECT_FALSE(resolveBeside(owner, "", "task").ok());
}

TEST(BesideFile, ALinkThatLeadsOutAndALookAlikeFolderAreOutside) {
  test::TempDir dir;
  fs::create_directories(dir.file("a/b"));
  fs::create_directories(dir.file("a/bc"));
  fs::create_directory_symlink(dir.file("a/bc"), dir.file("a/b/out"));
  EXPECT_TRUE(liesWithin(dir.file("a/b/x"), dir.file("a/b")));
  EXPECT_FALSE(liesWithin(dir.file("a/bc/x"), dir.file("a/b")));  // "a/bc" starts with "a/b" but is not in it
  EXPECT_FALSE(liesWithin(dir.file("a/b/out/x"), dir.file("a/b")));  // through a link to "a/bc"
  EXPECT_FALSE(resolveBeside(dir.file("a/b/s.dses"), "out/x.dvol", "tooth.file").ok());
}

}  // namespace
}  // namespace dentsim
