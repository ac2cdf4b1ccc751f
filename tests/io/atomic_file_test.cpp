// Tests of src/io/atomic_file.cpp: temporaries left by a killed writer are removed by the next write, a live writer's are kept, and only a regular file is replaced.
#include "io/atomic_file.h"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "test_support.h"

namespace dentsim {
namespace {

// The pid of a process that has ended and been reaped: no process has it until the system reuses it.
pid_t deadPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

std::set<std::string> filesIn(const test::TempDir& dir) {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) names.insert(e.path().filename().string());
  return names;
}

TEST(AtomicFile, AWriteRemovesTheTemporariesOfDeadWritersOfTheSameFile) {
  test::TempDir dir;
  const std::string dead = std::to_string(deadPid());
  const std::string live = std::to_string(::getppid());  // the process that started the tests is alive
  // What `kill -9` during a .dvol write leaves, beside a live writer's file and unrelated names.
  for (const std::string& name : std::vector<std::string>{"out.tmp-" + dead + "-0.dvol", "out.tmp-" + dead + "-17.dvol",
                                  "out.tmp-" + live + "-0.dvol", "other.tmp-" + dead + "-0.dvol",
                                  "out.tmp-" + dead + "-0.nii.gz", "out.tmp-x-0.dvol", "out.tmp--0.dvol"})
    test::writeBytes(dir.file(name), {1});
  ASSERT_TRUE(writeFileAtomic(dir.file("out.dvol"), std::vector<uint8_t>{7}).ok());
  // Only out.dvol's own temporaries of the dead pid are gone: another stem, another extension, a
  // live pid and names that are not temporaries stay.
  EXPECT_EQ(filesIn(dir), (std::set<std::string>{"out.dvol", "out.tmp-" + live + "-0.dvol", "other.tmp-" + dead + "-0.dvol",
                                                 "out.tmp-" + dead + "-0.nii.gz", "out.tmp-x-0.dvol", "out.tmp--0.dvol"}));
  EXPECT_EQ(test::readBytes(dir.file("out.dvol")), (std::vector<uint8_t>{7}));
}

TEST(AtomicFile, StaleTemporariesOfANameWithoutExtensionOrFolder) {
  test::TempDir dir;
  const std::string dead = std::to_string(deadPid());
  test::writeBytes(dir.file("report.tmp-" + dead + "-3"), {1});
  test::writeBytes(dir.file("report.tmp-" + dead + "-3.json"), {1});
  EXPECT_EQ(removeStaleTemporaries(dir.file("report")), 1);
  EXPECT_EQ(filesIn(dir), (std::set<std::string>{"report.tmp-" + dead + "-3.json"}));
  EXPECT_EQ(removeStaleTemporaries(dir.file("report.json")), 1);
  EXPECT_TRUE(filesIn(dir).empty());
}

TEST(AtomicFile, AFailedWriteLeavesNoTemporary) {
  test::TempDir dir;
  // The rename fails (a folder holds the name): the temporary is removed on that path too.
  std::filesystem::create_directories(dir.file("busy.dvol/keep"));
  EXPECT_FALSE(writeFileAtomic(dir.file("busy.dvol"), std::vector<uint8_t>{9}).ok());
  EXPECT_EQ(filesIn(dir), (std::set<std::string>{"busy.dvol"}));
}

// A device or FIFO at the output's name stays what it is: a rename would put a regular file in its
// place (as root, `-o /dev/null` replaced the machine's /dev/null). A FIFO stands in for the device.
TEST(AtomicFile, ANameThatIsNoRegularFileIsRefusedAndKept) {
  test::TempDir dir;
  const std::string fifo = dir.file("pipe.json");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const Status s = writeFileAtomic(fifo, std::vector<uint8_t>{1, 2, 3});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("not a regular file (a FIFO)"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find(fifo), std::string::npos) << s.error().message;
  struct stat st {};
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(filesIn(dir), (std::set<std::string>{"pipe.json"}));
}

}  // namespace
}  // namespace dentsim
