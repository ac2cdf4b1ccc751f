// Writes the DICOM fuzzer's seed slices (tests/fuzz/corpus/dicom_fuzzer/): the middle slice of its series, written a few ways.
//   build-fuzz/tests/fuzz/dicom_fuzz_seeds tests/fuzz/corpus/dicom_fuzzer
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "dicom_fuzz_series.h"
#include "io/dicom_series.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: dicom_fuzz_seeds OUT_DIR\n");
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path scratch = fs::temp_directory_path() / ("dentsim-dicom-seeds-" + std::to_string(::getpid()));
  fs::create_directories(out);
  // Each variant leads the reader down another path: the plain slice reads whole; the others reach
  // the unsigned and rescaled decode, and the mixed-modality and mixed-series refusals.
  struct Variant {
    const char* name;
    void (*edit)(dentsim::DicomWriteOptions&);
  };
  const Variant variants[] = {
      {"ct-int16", [](dentsim::DicomWriteOptions&) {}},
      {"ct-uint16-intercept", [](dentsim::DicomWriteOptions& o) { o.signed_pixels = false; o.rescale_intercept = -1024; }},
      {"ct-slope-half", [](dentsim::DicomWriteOptions& o) { o.rescale_slope = 0.5; }},
      {"mr-modality", [](dentsim::DicomWriteOptions& o) { o.modality = "MR"; o.hounsfield = false; }},
      {"other-series", [](dentsim::DicomWriteOptions& o) { o.series_uid = "2.25.40402026112900000000000000000002"; }},
  };
  for (const Variant& v : variants) {
    dentsim::DicomWriteOptions options = dentsim::fuzz::dicomFuzzOptions();
    v.edit(options);
    fs::remove_all(scratch);
    auto written = dentsim::writeDicomSeries(scratch.string(), dentsim::fuzz::dicomFuzzImage(), options);
    if (!written) {
      std::fprintf(stderr, "%s\n", written.error().message.c_str());
      return 1;
    }
    fs::copy_file(scratch / dentsim::fuzz::kDicomFuzzSlice, out / (std::string(v.name) + ".dcm"),
                  fs::copy_options::overwrite_existing);
  }
  fs::remove_all(scratch);
  return 0;
}
