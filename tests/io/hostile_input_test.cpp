// Every file reader against the wrong kind of file, a FIFO, a directory or a device, and the input budget: one clear line each, at once.
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <zstd.h>

#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/dvol_file.h"
#include "io/file_hash.h"
#include "io/file_kind.h"
#include "io/input_budget.h"
#include "io/nifti_labels.h"
#include "io/pen_path_file.h"
#include "io/ply_file.h"
#include "io/session_file.h"
#include "io/stl_file.h"
#include "io/wav_file.h"
#include "test_support.h"

namespace dentsim {
namespace {

// Every reader that takes a path, with the message it gives (empty when it reads the file).
struct Reader {
  const char* name;
  std::function<std::string(const std::string&)> read;
};

template <class R>
std::string messageOf(const R& r) {
  return r.ok() ? std::string() : r.message();
}

std::vector<Reader> readers() {
  return {
      {"bytes", [](const std::string& p) { return messageOf(readFileBytes(p, 1 << 20)); }},
      {"hash", [](const std::string& p) { return messageOf(fileHash(p)); }},
      {"stl", [](const std::string& p) { return messageOf(readStl(p)); }},
      {"ply", [](const std::string& p) { return messageOf(readPly(p)); }},
      {"dvol", [](const std::string& p) { return messageOf(readVolumeFile(p)); }},
      {"nifti", [](const std::string& p) { return messageOf(readNiftiLabels(p)); }},
      {"wav", [](const std::string& p) { return messageOf(readWav(p)); }},
      {"pen path", [](const std::string& p) { return messageOf(loadPenPath(p)); }},
      {"session", [](const std::string& p) { return messageOf(readSessionFile(p)); }},
  };
}

// Runs `body` in a child process that a 20 s alarm ends: a reader that blocked would make the test
// fail rather than hang. The alarm is only the safety net; the child's exit code is the assertion
// (0: every check held, else the number of the first reader that failed, plus 1).
int inChild(const std::function<int()>& body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::alarm(20);
    ::_exit(body());
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Each reader's message for `path` must start with the path and say `problem`.
void expectEveryReaderRefuses(const std::string& path, const std::string& problem) {
  const std::vector<Reader> all = readers();
  const int code = inChild([&] {
    for (size_t i = 0; i < all.size(); ++i) {
      const std::string m = all[i].read(path);
      if (m.rfind(path + ": ", 0) != 0 || m.find(problem) == std::string::npos || m.find('\n') != std::string::npos)
        return int(i) + 1;
    }
    return 0;
  });
  EXPECT_EQ(code, 0) << (code >= 1 && size_t(code) <= all.size() ? all[size_t(code) - 1].name : "killed or crashed")
                     << " did not refuse " << path << " with \"" << problem << "\"";
}

TEST(HostileInput, AFifoIsRefusedByEveryReaderWithoutBlocking) {
  test::TempDir dir;
  // The FIFOs given as an STL, a .dvol and a .dses blocked for ever.
  for (const char* name : {"pipe.stl", "pipe.nii", "pipe.dvol", "pipe.dses"}) {
    const std::string fifo = dir.file(name);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectEveryReaderRefuses(fifo, "not a regular file (a FIFO)");
  }
}

TEST(HostileInput, ADirectoryOrADeviceIsRefusedByEveryReader) {
  test::TempDir dir;
  const std::string folder = dir.file("folder.stl");
  std::filesystem::create_directory(folder);
  expectEveryReaderRefuses(folder, "not a regular file (a directory)");
  expectEveryReaderRefuses("/dev/null", "not a regular file (a character device)");
}

TEST(HostileInput, RequireRegularFileSaysWhatThePathIs) {
  test::TempDir dir;
  EXPECT_TRUE(requireRegularFile(dir.file("x")).message().find("cannot open: No such file") != std::string::npos);
  test::writeBytes(dir.file("x"), {1, 2, 3});
  EXPECT_TRUE(requireRegularFile(dir.file("x")).ok());
  // A link to a regular file is followed.
  std::filesystem::create_symlink(dir.file("x"), dir.file("link"));
  EXPECT_TRUE(requireRegularFile(dir.file("link")).ok());
  EXPECT_EQ(readFileHead(dir.file("link"), 2).value(), (std::vector<uint8_t>{1, 2}));
}

// ---- the wrong kind of file ---------------------------------------------------------------------

std::vector<uint8_t> bytesOf(const std::string& s) { return {s.begin(), s.end()}; }

// One small real file of each kind the readers may be handed by mistake, with its kind's name.
struct Sample {
  FileKind kind;
  std::string file;  // name in the temporary folder
};

class WrongKind : public ::testing::Test {
 protected:
  void SetUp() override {
    test::writeBytes(dir.file("mesh.ply"), bytesOf("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n"));
    LabelImage im;
    im.dims = {2, 2, 2};
    im.scanner_from_voxel = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    im.labels = {0, 1, 0, 1, 0, 1, 0, 1};
    ASSERT_TRUE(writeNiftiLabels(dir.file("labels.nii"), im).ok());
    ASSERT_TRUE(writeNiftiLabels(dir.file("labels.nii.gz"), im).ok());
    std::vector<uint8_t> packed(ZSTD_compressBound(1000));
    std::vector<uint8_t> zeros(1000, 0);
    packed.resize(ZSTD_compress(packed.data(), packed.size(), zeros.data(), zeros.size(), 3));
    test::writeBytes(dir.file("data.zst"), packed);
    VolumeFileData vol;
    vol.frame = VolumeFrame::axisAligned(6, 0.1, {0, 0, 0});
    vol.chunks = {0x80000000u};
    ASSERT_TRUE(writeVolumeFile(dir.file("tooth.dvol"), vol).ok());
    std::vector<uint8_t> wav = bytesOf("RIFF");
    for (uint8_t b : {36, 0, 0, 0}) wav.push_back(b);
    for (uint8_t b : bytesOf("WAVEfmt ")) wav.push_back(b);
    wav.resize(64, 0);
    test::writeBytes(dir.file("sound.wav"), wav);
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    png.resize(100, 7);
    test::writeBytes(dir.file("picture.png"), png);
    std::vector<uint8_t> dses = bytesOf("DSESSION");
    dses.resize(100, 0);
    test::writeBytes(dir.file("take.dses"), dses);
  }
  // Reads `file` (kept under its own name, or copied to `as`) with `read`; the message must name
  // the real kind.
  void expectNamed(const std::function<std::string(const std::string&)>& read, const std::string& file,
                   FileKind kind, const std::string& not_what, const std::string& as = "") {
    std::string path = dir.file(file);
    if (!as.empty()) {
      std::filesystem::copy_file(path, dir.file(as), std::filesystem::copy_options::overwrite_existing);
      path = dir.file(as);
    }
    const std::string m = read(path);
    const std::string expected = path + ": this is a " + fileKindName(kind) + " file, not " + not_what;
    EXPECT_EQ(m.rfind(expected, 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  const std::vector<Sample> samples = {
      {FileKind::Ply, "mesh.ply"},      {FileKind::Nifti1, "labels.nii"}, {FileKind::Gzip, "labels.nii.gz"},
      {FileKind::Zstd, "data.zst"},     {FileKind::Dvol, "tooth.dvol"},   {FileKind::Wav, "sound.wav"},
      {FileKind::Png, "picture.png"},   {FileKind::Dses, "take.dses"},
  };
  test::TempDir dir;
};

TEST_F(WrongKind, EverySampleIsRecognised) {
  for (const Sample& s : samples) EXPECT_EQ(sniffFileKind(test::readBytes(dir.file(s.file))), s.kind) << s.file;
  EXPECT_EQ(sniffFileKind(bytesOf("solid cube\nfacet normal 0 0 1\n")), FileKind::Unknown);
  EXPECT_EQ(sniffFileKind({}), FileKind::Unknown);
  EXPECT_EQ(sniffFileKind(bytesOf("pl")), FileKind::Unknown);
}

TEST_F(WrongKind, StlNamesWhatTheFileReallyIs) {
  // Before, a PLY, .nii.gz or .dvol given as STL read as "binary STL header says 1835627374 triangles".
  for (const Sample& s : samples)
    expectNamed([](const std::string& p) { return messageOf(readStl(p)); }, s.file, s.kind, "an STL mesh", "x.stl");
}

TEST_F(WrongKind, PlyDvolWavAndPenPathNameWhatTheFileReallyIs) {
  for (const Sample& s : samples) {
    if (s.kind != FileKind::Ply)
      expectNamed([](const std::string& p) { return messageOf(readPly(p)); }, s.file, s.kind, "a PLY mesh");
    if (s.kind != FileKind::Dvol)
      expectNamed([](const std::string& p) { return messageOf(readVolumeFile(p)); }, s.file, s.kind,
                  "a dentsim volume (.dvol)");
    if (s.kind != FileKind::Wav)
      expectNamed([](const std::string& p) { return messageOf(readWav(p)); }, s.file, s.kind, "a WAV sound");
    expectNamed([](const std::string& p) { return messageOf(loadPenPath(p)); }, s.file, s.kind,
                "a pen path (CSV or JSON)");
  }
}

TEST_F(WrongKind, NiftiNamesWhatTheFileReallyIs) {
  for (const Sample& s : samples) {
    if (s.kind == FileKind::Nifti1 || s.kind == FileKind::Gzip) continue;
    // Under a .nii name, libnifti fails first; under another name, the name check does.
    expectNamed([](const std::string& p) { return messageOf(readNiftiLabels(p)); }, s.file, s.kind,
                "a NIfTI label volume", "as.nii");
    expectNamed([](const std::string& p) { return messageOf(readNiftiLabels(p)); }, s.file, s.kind,
                "a NIfTI label volume (.nii or .nii.gz)");
  }
}

// ---- the budget -----------------------------------------------------------------------------------

// Restores the default budget when a test ends.
struct BudgetScope {
  explicit BudgetScope(uint64_t bytes) { setInputBudget({bytes}); }
  ~BudgetScope() { setInputBudget({}); }
};

TEST(InputBudget, RefusalsOnTheBudgetNameTheFlag) {
  EXPECT_EQ(inputBudget().max_bytes, uint64_t{512} << 20);
  EXPECT_EQ(limitExceeded("file of 9 bytes", 8), "file of 9 bytes exceeds the limit of 8 bytes");
  const BudgetScope budget(1000);
  EXPECT_EQ(limitExceeded("file of 1001 bytes", 1000),
            "file of 1001 bytes exceeds the limit of 1000 bytes (the input budget; raise it with --max-input-mb N, in MiB)");
  test::TempDir dir;
  std::vector<uint8_t> big(84 + 50 * 20, 0);
  big[80] = 20;  // a consistent binary STL of 20 (degenerate) triangles, 1084 bytes
  test::writeBytes(dir.file("big.stl"), big);
  const std::string m = messageOf(readStl(dir.file("big.stl")));
  EXPECT_EQ(m, dir.file("big.stl") + ": file of 1084 bytes exceeds the limit of 1000 bytes (the input budget; "
                                     "raise it with --max-input-mb N, in MiB)");
}

TEST(InputBudget, AnStlCountIsCheckedAgainstTheSizeBeforeTheFileIsRead) {
  test::TempDir dir;
  // 284 bytes claiming 20 000 000 triangles: refused from the first 84 bytes and the size alone.
  std::vector<uint8_t> claim(284, 0);
  const uint32_t count = 20'000'000;
  std::memcpy(claim.data() + 80, &count, 4);
  test::writeBytes(dir.file("claim.stl"), claim);
  EXPECT_EQ(messageOf(readStl(dir.file("claim.stl"))),
            dir.file("claim.stl") + ": binary STL header says 20000000 triangles (1000000084 bytes) but the file has "
                                    "284 bytes (truncated?)");
  // A consistent file over the triangle limit is refused before its records are read.
  std::vector<uint8_t> over(84 + 50 * 5, 0);
  over[80] = 5;
  test::writeBytes(dir.file("over.stl"), over);
  StlReadLimits limits;
  limits.max_triangles = 4;
  EXPECT_NE(messageOf(readStl(dir.file("over.stl"), limits)).find("5 triangles exceed the limit of 4"), std::string::npos);
}

}  // namespace
}  // namespace dentsim
