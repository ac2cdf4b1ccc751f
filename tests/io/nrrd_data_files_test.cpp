// The data files a NRRD header names, read as Teem reads them: the three forms, Teem's line and path rules, formats other than one %d refused, and long headers checked to their end.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <fstream>

#include "io/grey_volume_file.h"
#include "io/nrrd_data_files.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::TempDir;

void write(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

const std::string kHead = "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nencoding: raw\nendian: little\n";  // 6 lines

std::vector<std::string> names(const std::string& text, const std::string& header = "dir/a.nhdr") {
  Result<std::vector<std::string>> n = nrrdDataFileNames(text, header);
  EXPECT_TRUE(n) << n.message();
  return n ? *n : std::vector<std::string>{};
}

// Teem prints the format with sprintf; anything but one %d (width at most 9) would let the file's
// text read or write memory, or would be a name to Teem while it looks like a format here.
TEST(NrrdDataFiles, FormatsOtherThanOneIntegerAreRefusedNamingTheLine) {
  for (const char* format : {"x%n%n%n%n.raw 1 1 1", "x%s.raw 1 1 1", "x%x.raw 1 1 1", "x%%.raw 1 1 1",
                             "x%10000d.raw 1 1 1", "x%d%n.raw 1 2 1", "x%u.raw 1 1 1", "x%-3d.raw 1 1 1",
                             "x%d.raw 1 2 1 %n", "x%d.raw 1 two 1", "x%d.raw 1 9999999999 1"}) {
    Result<std::vector<std::string>> n = nrrdDataFileNames(kHead + "data file: " + format + "\n\n", "a.nhdr");
    ASSERT_FALSE(n) << format;
    EXPECT_EQ(n.message().rfind("a.nhdr: line 7: data file '", 0), 0u) << n.message();
    EXPECT_EQ(n.message().find('\n'), std::string::npos) << n.message();
  }
}

TEST(NrrdDataFiles, FormatNamesAreNumberedAsPrintfWould) {
  EXPECT_EQ(names(kHead + "data file: s%03d.raw -1 1 1\n\n"),
            (std::vector<std::string>{"dir/s-01.raw", "dir/s000.raw", "dir/s001.raw"}));
  EXPECT_EQ(names(kHead + "data file: /abs/s%2d.raw 12 8 -4 2\n\n"),
            (std::vector<std::string>{"/abs/s12.raw", "/abs/s 8.raw"}));
  // A step that never reaches MAX is Teem's own error, before it opens anything.
  EXPECT_TRUE(names(kHead + "data file: s%d.raw 1 5 -1\n\n").empty());
}

// The name is the whole rest of the line, as Teem takes it; "-" and "?:..." stand as they are.
TEST(NrrdDataFiles, NamesAndPathsFollowTeem) {
  EXPECT_EQ(names(kHead + "data file:   a b.raw \n\n"), (std::vector<std::string>{"dir/a b.raw "}));
  EXPECT_EQ(names(kHead + "data file: c:x.raw\n\n"), (std::vector<std::string>{"c:x.raw"}));
  EXPECT_EQ(names(kHead + "data file: -\n\n"), (std::vector<std::string>{"-"}));
  EXPECT_EQ(names(kHead + "DataFile: x.raw\n\n", "a.nhdr"), (std::vector<std::string>{"./x.raw"}));
  // Comments and key/value pairs name nothing; a LIST names every line after it.
  EXPECT_EQ(names(kHead + "# data file: no.raw\ndata file:=no.raw\ndata file: LIST\none.raw\ntwo.raw\n"),
            (std::vector<std::string>{"dir/one.raw", "dir/two.raw"}));
  // A line's text ends at a NUL byte, as Teem's C string does.
  EXPECT_EQ(names(kHead + std::string("data file: x.raw\0.fifo\n\n", 25)), (std::vector<std::string>{"dir/x.raw"}));
}

// Teem ends a line at "\r" as at "\n", and the header at its first empty line: what follows is data.
TEST(NrrdDataFiles, LinesAndTheHeaderEndWhereTeemEndsThem) {
  EXPECT_EQ(names("NRRD0004\rtype: short\r\ndata file: p.raw\r\rdata file: q.raw\n"),
            (std::vector<std::string>{"dir/p.raw"}));
  EXPECT_TRUE(names(kHead + "\ndata file: attached-data.raw\n").empty());
}

// Every line is read, however many comments come first, up to a stated limit.
TEST(NrrdDataFiles, LongHeadersAreCheckedToTheirEnd) {
  TempDir tmp;
  ASSERT_EQ(::mkfifo(tmp.file("pipe.raw").c_str(), 0600), 0);
  std::string comments;
  for (int n = 0; n < 10000; ++n) comments += "# comment\n";
  write(tmp.file("comments.nhdr"), kHead + comments + "data file: pipe.raw\n\n");
  std::string list;
  for (int n = 1; n <= 10500; ++n) list += (n == 10401 ? std::string("pipe.raw") : "s" + std::to_string(n) + ".raw") + "\n";
  for (int n = 1; n <= 10500; ++n)
    if (n != 10401) write(tmp.file("s" + std::to_string(n) + ".raw"), "");
  write(tmp.file("list.nhdr"), kHead + "data file: LIST\n" + list);
  for (const char* header : {"comments.nhdr", "list.nhdr"}) {
    Status s = checkNrrdDataFiles(tmp.file(header));
    ASSERT_FALSE(s) << header;
    EXPECT_NE(s.message().find("data file " + tmp.file("pipe.raw") + ": not a regular file (a FIFO)"), std::string::npos)
        << s.message();
  }
  std::string many;
  for (size_t n = 0; n <= kNrrdMaxHeaderLines; ++n) many += "#\n";
  write(tmp.file("many.nhdr"), kHead + many + "data file: pipe.raw\n\n");
  Status s = checkNrrdDataFiles(tmp.file("many.nhdr"));
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("more than 100000 lines"), std::string::npos) << s.message();
}

// A name shown in a message is escaped: it cannot break the line or reach the terminal raw.
TEST(NrrdDataFiles, NamesInMessagesAreEscaped) {
  TempDir tmp;
  write(tmp.file("esc.nhdr"), kHead + "data file: \x1b[2Jgone.raw\n\n");
  Status s = checkNrrdDataFiles(tmp.file("esc.nhdr"));
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("\\x1b[2Jgone.raw"), std::string::npos) << s.message();
  EXPECT_EQ(s.message().find('\x1b'), std::string::npos);
  Result<GreyImage> g = readGreyVolume(tmp.file("esc.nhdr"));
  ASSERT_FALSE(g);
  EXPECT_EQ(g.message().find('\x1b'), std::string::npos);
}

}  // namespace
}  // namespace dentsim
