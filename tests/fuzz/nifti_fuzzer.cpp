// libFuzzer entry for the NIfTI label reader: the input is written to a temporary .nii file, as libnifti reads files.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "io/nifti_labels.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/dentsim-nifti-fuzz-" + std::to_string(::getpid()) + ".nii";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  dentsim::NiftiReadLimits limits;
  limits.max_voxels = int64_t{1} << 24;
  limits.max_label_bytes = uint64_t{32} << 20;  // a forged header must not make the fuzzer run out of memory
  (void)dentsim::readNiftiLabels(path, limits);
  return 0;
}
