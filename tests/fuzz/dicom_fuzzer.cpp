// libFuzzer entry for the DICOM reader: the input is written as the middle slice of a three-slice series, as GDCM reads files.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include <sanitizer/common_interface_defs.h>

#include "dicom_fuzz_series.h"
#include "io/dicom_series.h"

namespace {

// GDCM as Debian builds it keeps its assertions, and damaged headers reach them within seconds (a
// file meta header cut short aborts in gdcm::ReadExplicitDataElement); a forged element length
// makes it allocate and fill up to 4 GB. dentsim meets both in its checking child (io/dicom_series.h,
// section 5), which caps the child's data segment and processor time; here they would end every run
// in its first minute, or slow it to a few inputs a second. So each input is first read in a forked
// child with caps like those, and one that GDCM aborts on, or that runs into a cap, is left there.
// An abort is GDCM's: this build (RelWithDebInfo) compiles dentsim's own asserts out. A sanitizer's
// report (exit kSanitizerExit) that is not about memory running out sends the input on to the read
// in this process, which reports it as a crash with its stack. The child's coverage is not counted;
// the read that follows here is.
constexpr int kSanitizerExit = 99;
// The data segment's growth beyond max_bytes [B]: dentsim's child allows 256 MB, but this series is
// 144 voxels, and GDCM filling a forged length of 100 MB in this process costs a second an input.
constexpr uint64_t kChildSlackBytes = uint64_t{32} << 20;
constexpr rlim_t kChildCpuS = 5;  // processor time of one read [s]

uint64_t dataSegmentBytes() {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  unsigned long long kb = 0;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "VmData: %llu kB", &kb) == 1) break;
  std::fclose(f);
  return uint64_t(kb) * 1024;
}

bool leaveToTheChild(const std::string& dir, const dentsim::DicomReadOptions& options) {
  FILE* report = std::tmpfile();  // the child's stderr, for the sanitizer's reason
  if (!report) return false;
  const uint64_t data_now = dataSegmentBytes();
  std::fflush(nullptr);
  const pid_t child = ::fork();
  if (child < 0) {
    std::fclose(report);
    return false;
  }
  if (child == 0) {
    std::signal(SIGABRT, SIG_DFL);  // not libFuzzer's handler, which would report GDCM's abort as a crash
    __sanitizer_set_death_callback([] { ::_exit(kSanitizerExit); });  // nor write the child's artifacts
    ::dup2(::fileno(report), STDERR_FILENO);
    const rlimit no_core{0, 0}, cpu{kChildCpuS, kChildCpuS + 1};
    ::setrlimit(RLIMIT_CORE, &no_core);
    ::setrlimit(RLIMIT_CPU, &cpu);
    if (data_now > 0) {
      const rlim_t cap = rlim_t(data_now + options.max_bytes + kChildSlackBytes);
      const rlimit data{cap, cap};
      ::setrlimit(RLIMIT_DATA, &data);
    }
    (void)dentsim::readDicomSeries(dir, options);
    ::_exit(0);
  }
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  std::string said(4096, '\0');
  std::rewind(report);
  said.resize(std::fread(said.data(), 1, said.size(), report));
  std::fclose(report);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return false;
  if (WIFEXITED(status) && WEXITSTATUS(status) == kSanitizerExit)
    return said.find("out of memory") != std::string::npos || said.find("out-of-memory") != std::string::npos ||
           said.find("failed to allocate") != std::string::npos ||
           said.find("allocation-size-too-big") != std::string::npos;
  return true;  // SIGABRT (GDCM's assertion), SIGXCPU or SIGKILL (the processor time cap)
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string dir = "/tmp/dentsim-dicom-fuzz-" + std::to_string(::getpid());
  static const bool made = [] {
    std::filesystem::remove_all(dir);
    return dentsim::writeDicomSeries(dir, dentsim::fuzz::dicomFuzzImage(), dentsim::fuzz::dicomFuzzOptions()).ok();
  }();
  if (!made) return 0;
  FILE* f = std::fopen((dir + "/" + dentsim::fuzz::kDicomFuzzSlice).c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  dentsim::DicomReadOptions options;
  options.max_bytes = uint64_t{32} << 20;  // a forged size must not make the fuzzer run out of memory
  // In this process: libFuzzer sees no coverage, and no crash, in the reader's own forked checking child.
  options.in_process = true;
  if (leaveToTheChild(dir, options)) return -1;  // -1: libFuzzer keeps it out of the corpus
  (void)dentsim::readDicomSeries(dir, options);
  return 0;
}
