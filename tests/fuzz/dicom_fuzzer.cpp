// libFuzzer entry for the DICOM reader: the input is written as the middle slice of a three-slice series, as GDCM reads files.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "io/dicom_series.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string dir = "/tmp/dentsim-dicom-fuzz-" + std::to_string(::getpid());
  static const bool made = [] {
    dentsim::GreyImage g;
    g.dims = {8, 6, 3};
    g.scanner_from_voxel = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0};
    g.values.assign(144, 100.0f);
    std::filesystem::remove_all(dir);
    return dentsim::writeDicomSeries(dir, g).ok();
  }();
  if (!made) return 0;
  FILE* f = std::fopen((dir + "/slice-0002.dcm").c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  dentsim::DicomReadOptions options;
  options.max_bytes = uint64_t{32} << 20;  // a forged size must not make the fuzzer run out of memory
  (void)dentsim::readDicomSeries(dir, options);
  return 0;
}
