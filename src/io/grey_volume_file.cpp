// NRRD grey volumes through Teem, and the choice of reader by file name for `voxelize --ct`.
#include "io/grey_volume_file.h"

#include <teem/nrrd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "io/atomic_file.h"
#include "io/nifti_labels.h"
#include "io/nrrd_data_files.h"
#include "io/parse_guard.h"

namespace dentsim {
namespace {

bool endsWith(const std::string& s, const char* suffix) {
  const size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

struct NrrdNuke {
  void operator()(Nrrd* n) const { nrrdNuke(n); }
};
using NrrdPtr = std::unique_ptr<Nrrd, NrrdNuke>;

struct IoNix {
  void operator()(NrrdIoState* s) const { nrrdIoStateNix(s); }
};

// Teem keeps its errors in a "biff" stack; the last line says the most.
std::string teemError() {
  char* e = biffGetDone(NRRD);
  std::string text = e ? e : "";
  std::free(e);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  const size_t last = text.rfind('\n');
  std::string line = last == std::string::npos ? text : text.substr(last + 1);
  if (const size_t bracket = line.find("] "); line.rfind('[', 0) == 0 && bracket != std::string::npos)
    line = line.substr(bracket + 2);  // "[nrrd] _nrrdRead: ..." -> "_nrrdRead: ..."
  return line.empty() ? "unreadable" : escapeControl(line, 300, true);  // it quotes the header's text
}

double mmPerUnit(const char* unit) {
  if (!unit || !*unit) return 1.0;
  const std::string u = unit;
  if (u == "mm" || u == "millimeter" || u == "millimeters") return 1.0;
  if (u == "um" || u == "micron" || u == "microns" || u == "micrometer") return 1e-3;
  if (u == "cm") return 10.0;
  if (u == "m" || u == "meter" || u == "meters") return 1000.0;
  return -1.0;
}

template <class T>
void toFloats(const void* data, size_t n, std::vector<float>& out) {
  const T* src = static_cast<const T*>(data);
  for (size_t i = 0; i < n; ++i) {
    const float f = float(src[i]);
    out[i] = std::isfinite(f) ? f : 0.0f;
  }
}

}  // namespace

Result<GreyImage> readNrrdGrey(const std::string& path, uint64_t max_bytes, const ScanReadApproval& approve) {
  nrrdStateVerboseIO = 0;  // Teem's warnings on stderr; its errors come back through biff into one line
  if (Status s = requireRegularFile(path); !s) return s.error();
  if (Status s = checkNrrdDataFiles(path); !s) return s.error();  // io/nrrd_data_files.h says why
  // 1. The header alone.
  NrrdPtr header(nrrdNew());
  {
    std::unique_ptr<NrrdIoState, IoNix> io(nrrdIoStateNew());
    io->skipData = AIR_TRUE;
    if (nrrdLoad(header.get(), path.c_str(), io.get()) != 0)
      return makeError(path, "not a readable NRRD file (" + teemError() + ")");
  }
  const Nrrd& h = *header;
  unsigned dim = h.dim;
  while (dim > 3 && h.axis[dim - 1].size == 1) --dim;
  if (dim != 3) return makeError(path, "a " + std::to_string(h.dim) + "D NRRD; a scan is a 3D volume of one value a voxel");
  uint64_t voxels = 1;
  std::array<int32_t, 3> dims{};
  for (unsigned a = 0; a < 3; ++a) {
    const size_t n = h.axis[a].size;
    if (n < 1 || n > (size_t{1} << 20)) return makeError(path, "axis " + std::to_string(a) + " has " + std::to_string(n) + " samples");
    dims[a] = int32_t(n);
    voxels *= n;
  }
  if (voxels > max_bytes / sizeof(float))
    return makeError(path, limitExceeded("a volume of " + std::to_string(voxels) + " voxels as float", max_bytes));
  switch (h.type) {
    case nrrdTypeChar: case nrrdTypeUChar: case nrrdTypeShort: case nrrdTypeUShort: case nrrdTypeInt:
    case nrrdTypeUInt: case nrrdTypeFloat: case nrrdTypeDouble: break;
    default: return makeError(path, std::string("NRRD type ") + airEnumStr(nrrdType, h.type) + " is not a scan's grey value");
  }
  // Teem loads the whole data in the file's type before it becomes floats.
  if (approve)
    if (Status s = approve(voxels, uint32_t(nrrdTypeSize[h.type])); !s) return s.error();

  // 2. Geometry: space directions and origin, else per-axis spacing.
  GreyImage image;
  image.dims = dims;
  std::array<double, 12>& m = image.scanner_from_voxel;
  m = {};
  if (h.spaceDim > 0) {
    if (h.spaceDim != 3) return makeError(path, "a " + std::to_string(h.spaceDim) + "D space; a scan lies in 3D");
    for (unsigned r = 0; r < 3; ++r) {
      const double unit = mmPerUnit(h.spaceUnits[r]);
      if (unit < 0) return makeError(path, "unknown space unit '" + escapeControl(h.spaceUnits[r], 40, true) + "'");
      const double origin = std::isfinite(h.spaceOrigin[r]) ? h.spaceOrigin[r] : 0.0;
      m[4 * r + 3] = origin * unit;
      for (unsigned a = 0; a < 3; ++a) {
        const double d = h.axis[a].spaceDirection[r];
        if (!std::isfinite(d)) return makeError(path, "axis " + std::to_string(a) + " has no space direction");
        m[4 * r + a] = d * unit;
      }
    }
  } else {
    for (unsigned a = 0; a < 3; ++a) {
      const double s = std::isfinite(h.axis[a].spacing) ? h.axis[a].spacing : 1.0;
      m[5 * a] = s;
    }
  }
  for (unsigned a = 0; a < 3; ++a) {
    image.pitch_mm[a] = std::sqrt(m[a] * m[a] + m[4 + a] * m[4 + a] + m[8 + a] * m[8 + a]);
    if (!(image.pitch_mm[a] > 0) || !std::isfinite(image.pitch_mm[a]))
      return makeError(path, "axis " + std::to_string(a) + " has no length (space direction or spacing 0)");
  }
  const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                     m[2] * (m[4] * m[9] - m[5] * m[8]);
  if (!(std::fabs(det) > 1e-12 * image.pitch_mm[0] * image.pitch_mm[1] * image.pitch_mm[2]))
    return makeError(path, "the space directions are not independent");

  // 3. The data.
  NrrdPtr full(nrrdNew());
  if (nrrdLoad(full.get(), path.c_str(), nullptr) != 0)
    return makeError(path, "truncated or damaged NRRD data (" + teemError() + ")");
  if (nrrdElementNumber(full.get()) != voxels || full->type != h.type || !full->data)
    return makeError(path, "the NRRD data differs from its header");
  image.values.resize(voxels);
  switch (full->type) {
    case nrrdTypeChar: toFloats<signed char>(full->data, voxels, image.values); break;
    case nrrdTypeUChar: toFloats<unsigned char>(full->data, voxels, image.values); break;
    case nrrdTypeShort: toFloats<int16_t>(full->data, voxels, image.values); break;
    case nrrdTypeUShort: toFloats<uint16_t>(full->data, voxels, image.values); break;
    case nrrdTypeInt: toFloats<int32_t>(full->data, voxels, image.values); break;
    case nrrdTypeUInt: toFloats<uint32_t>(full->data, voxels, image.values); break;
    case nrrdTypeFloat: toFloats<float>(full->data, voxels, image.values); break;
    default: toFloats<double>(full->data, voxels, image.values); break;
  }
  image.unit = GreyUnit::Raw;
  return image;
}

Result<GreyImage> readGreyVolume(const std::string& path, uint64_t max_bytes, const ScanReadApproval& approve) {
  if (endsWith(path, ".nii") || endsWith(path, ".nii.gz")) {
    NiftiReadLimits limits;
    limits.max_label_bytes = max_bytes / 2;  // the NIfTI reader allows the floats twice its label budget
    limits.approve = approve;
    return readNiftiGrey(path, limits);
  }
  if (endsWith(path, ".nrrd") || endsWith(path, ".nhdr")) return readNrrdGrey(path, max_bytes, approve);
  return makeError(path, "not a grey-value volume's name (expected .nii, .nii.gz, .nrrd or .nhdr; a DICOM folder goes to --dicom)");
}

}  // namespace dentsim
