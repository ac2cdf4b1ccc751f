// libFuzzer entry for the NRRD grey-volume reader: the input is written to a temporary .nrrd file, as Teem reads files.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "io/grey_volume_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/dentsim-nrrd-fuzz-" + std::to_string(::getpid()) + ".nrrd";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  (void)dentsim::readNrrdGrey(path, uint64_t{32} << 20);  // a forged size must not exhaust the fuzzer's memory
  return 0;
}
