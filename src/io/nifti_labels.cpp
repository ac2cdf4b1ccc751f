// NIfTI volumes (segmented labels, and a scanner's grey values): the header is checked before libnifti allocates or reads voxels, and label writes are atomic.
//
// Contents
//   1. Small helpers: messages, file names, matrices
//   2. Header check (the raw header, before any voxel is read)
//   3. Voxel conversion into int16 labels; opening and geometry shared by both readers
//   4. readNiftiLabels and readNiftiGrey
//   5. writeNiftiLabels
#include "io/nifti_labels.h"

#include <sys/stat.h>

#include <nifti2_io.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>

#include "io/atomic_file.h"
#include "io/file_kind.h"
#include "io/input_budget.h"

namespace dentsim {
namespace {

// ---- 1. helpers -----------------------------------------------------------------------------

// libnifti reports failures on stderr; we report them ourselves, in one line.
void silenceNifti() { nifti_set_debug_level(0); }

bool endsWith(const std::string& s, const char* suffix) {
  const size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

bool isGzipName(const std::string& path) { return endsWith(path, ".nii.gz"); }

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

struct NimDeleter {
  void operator()(nifti_image* nim) const { nifti_image_free(nim); }
};
using NimPtr = std::unique_ptr<nifti_image, NimDeleter>;

struct FreeDeleter {
  void operator()(void* p) const { std::free(p); }
};

double det3(const std::array<double, 12>& m) {
  return m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
         m[2] * (m[4] * m[9] - m[5] * m[8]);
}

std::array<double, 12> fromDmat44(const nifti_dmat44& d, double scale) {
  std::array<double, 12> m{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[size_t(4 * r + c)] = d.m[r][c] * scale;
  return m;
}

// True when the file's first word is a NIfTI header size (348 or 540, either byte order): such a
// file that libnifti cannot read is a damaged NIfTI file rather than some other kind of file.
bool startsLikeNifti(const std::string& path, bool gz) {
  znzFile fp = znzopen(path.c_str(), "rb", gz ? 1 : 0);
  if (znz_isnull(fp)) return false;
  uint8_t b[4] = {0, 0, 0, 0};
  const size_t got = znzread(b, 1, 4, fp);
  znzclose(fp);
  if (got != 4) return false;
  const uint32_t le = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
  const uint32_t be = uint32_t(b[3]) | uint32_t(b[2]) << 8 | uint32_t(b[1]) << 16 | uint32_t(b[0]) << 24;
  return le == 348 || le == 540 || be == 348 || be == 540;
}

// ---- 2. header check ------------------------------------------------------------------------

// What the raw header says, in one form for NIfTI-1 and NIfTI-2.
struct HeaderInfo {
  int version = 0;                      // 1 or 2
  std::array<int64_t, 8> dim{};         // dim[0] = rank
  std::array<double, 8> pixdim{};
  int datatype = 0;
  double vox_offset = 0;                // [B]
  double scl_slope = 0, scl_inter = 0;
  int xyzt_units = 0;
  bool single_file = false;             // magic "n+1"/"n+2"
};

HeaderInfo headerInfo(const void* raw, int version) {
  HeaderInfo h;
  h.version = version;
  if (version == 1) {
    const auto* n1 = static_cast<const nifti_1_header*>(raw);
    for (size_t i = 0; i < 8; ++i) {
      h.dim[i] = n1->dim[i];
      h.pixdim[i] = n1->pixdim[i];
    }
    h.datatype = n1->datatype;
    h.vox_offset = n1->vox_offset;
    h.scl_slope = n1->scl_slope;
    h.scl_inter = n1->scl_inter;
    h.xyzt_units = n1->xyzt_units;
    h.single_file = std::memcmp(n1->magic, "n+1", 4) == 0;
  } else {
    const auto* n2 = static_cast<const nifti_2_header*>(raw);
    for (size_t i = 0; i < 8; ++i) {
      h.dim[i] = n2->dim[i];
      h.pixdim[i] = n2->pixdim[i];
    }
    h.datatype = n2->datatype;
    h.vox_offset = double(n2->vox_offset);
    h.scl_slope = n2->scl_slope;
    h.scl_inter = n2->scl_inter;
    h.xyzt_units = n2->xyzt_units;
    h.single_file = std::memcmp(n2->magic, "n+2", 4) == 0;
  }
  return h;
}

// Bytes per stored voxel of the datatypes we accept; 0 for any other.
int acceptedBytesPerVoxel(int datatype) {
  switch (datatype) {
    case DT_UINT8: case DT_INT8: return 1;
    case DT_INT16: case DT_UINT16: return 2;
    case DT_INT32: case DT_UINT32: case DT_FLOAT32: return 4;
    case DT_FLOAT64: return 8;
    default: return 0;
  }
}

std::string datatypeName(int datatype) {
  const char* s = nifti_datatype_string(datatype);
  return (s && std::strcmp(s, "DT_UNKNOWN") != 0) ? std::string(s) : "code " + std::to_string(datatype);
}

// Millimetres per header spatial unit; unknown units are read as mm, as most label tools write them.
double mmPerUnit(int xyzt_units) {
  switch (XYZT_TO_SPACE(xyzt_units)) {
    case NIFTI_UNITS_METER: return 1000.0;
    case NIFTI_UNITS_MICRON: return 0.001;
    default: return 1.0;
  }
}

struct CheckedHeader {
  std::array<int32_t, 3> dims{};
  int bytes_per_voxel = 0;
  int64_t voxels = 0;
  uint64_t data_bytes = 0;   // voxel bytes the file must hold [B]
};

// `grey`: a scanner's grey values, which may be scaled and stored as any number type; otherwise labels.
Result<CheckedHeader> checkHeader(const HeaderInfo& h, const std::string& path, const NiftiReadLimits& limits,
                                  bool grey) {
  if (!h.single_file)
    return makeError(path, "not a single-file NIfTI image (no \"n+1\"/\"n+2\" magic; .hdr/.img pairs "
                           "and Analyze files are not supported)");
  const int64_t rank = h.dim[0];
  if (rank < 3 || rank > 7)
    return makeError(path, "wrong dimensionality: dim[0] = " + std::to_string(rank) + ", expected a 3D image");
  for (int64_t i = 1; i <= 3; ++i)
    if (h.dim[size_t(i)] <= 0)
      return makeError(path, "invalid dimensions: dim[" + std::to_string(i) + "] = " +
                                 std::to_string(h.dim[size_t(i)]));
  for (int64_t i = 4; i <= rank; ++i)
    if (h.dim[size_t(i)] != 1)
      return makeError(path, "wrong dimensionality: a " + std::to_string(rank) + "D image with dim[" +
                                 std::to_string(i) + "] = " + std::to_string(h.dim[size_t(i)]) +
                                 ", expected a single 3D volume");
  // Multiply step by step so that a hostile header cannot overflow the count.
  int64_t voxels = 1;
  for (size_t i = 1; i <= 3; ++i) {
    if (h.dim[i] > limits.max_voxels || voxels > limits.max_voxels / h.dim[i])
      return makeError(path, "oversized dimensions " + std::to_string(h.dim[1]) + " x " +
                                 std::to_string(h.dim[2]) + " x " + std::to_string(h.dim[3]) +
                                 " exceed the limit of " + std::to_string(limits.max_voxels) + " voxels");
    voxels *= h.dim[i];
  }
  const int bpv = acceptedBytesPerVoxel(h.datatype);
  if (bpv == 0)
    return makeError(path, "unsupported datatype " + datatypeName(h.datatype) +
                               (grey ? std::string(" for grey values (expected uint8, int8, int16, uint16, int32, uint32, "
                                                   "float32 or float64)")
                                     : std::string(" for labels (expected uint8, int8, int16, uint16, int32, uint32, or "
                                                   "float32/float64 holding whole numbers)")));
  const uint64_t bytes = uint64_t(voxels) * uint64_t(bpv);
  if (bytes > limits.max_bytes)
    return makeError(path, "voxel data of " + std::to_string(bytes) + " bytes exceeds the limit of " +
                               std::to_string(limits.max_bytes) + " bytes");
  const bool scaled = std::isfinite(h.scl_slope) && h.scl_slope != 0.0 &&
                      !(h.scl_slope == 1.0 && h.scl_inter == 0.0);
  if (scaled && !grey)
    return makeError(path, "labels are scaled (scl_slope " + num(h.scl_slope) + ", scl_inter " +
                               num(h.scl_inter) + "); a label image must store its codes unscaled");
  for (size_t i = 1; i <= 3; ++i)
    if (!std::isfinite(h.pixdim[i]) || h.pixdim[i] <= 0.0 || h.pixdim[i] > 1e9)
      return makeError(path, "invalid voxel size pixdim[" + std::to_string(i) + "] = " + num(h.pixdim[i]));
  const double min_offset = h.version == 1 ? 352.0 : 544.0;  // header plus the 4-byte extender
  if (!std::isfinite(h.vox_offset) || h.vox_offset < min_offset - 4.0 || h.vox_offset > 1e12)
    return makeError(path, "invalid voxel data offset " + num(h.vox_offset));
  CheckedHeader c;
  c.dims = {int32_t(h.dim[1]), int32_t(h.dim[2]), int32_t(h.dim[3])};
  c.bytes_per_voxel = bpv;
  c.voxels = voxels;
  c.data_bytes = bytes;
  return c;
}

// ---- 3. voxel conversion --------------------------------------------------------------------

// A slab of `n` stored voxels starting at voxel `first`, converted into out[first ..]. Returns how
// many were not 0.
template <class T>
Result<size_t> convertInts(const void* data, size_t first, size_t n, std::vector<Label>& out, const std::string& path) {
  const T* src = static_cast<const T*>(data);
  size_t nonzero = 0;
  for (size_t i = 0; i < n; ++i) {
    const T v = src[i];
    if constexpr (!std::is_same_v<T, Label>) {
      if (int64_t(v) < std::numeric_limits<Label>::min() || int64_t(v) > std::numeric_limits<Label>::max())
        return makeError(path, "label " + std::to_string(int64_t(v)) + " at voxel " + std::to_string(first + i) +
                                   " does not fit the 16-bit label range");
    }
    out[first + i] = static_cast<Label>(v);
    nonzero += v != 0;
  }
  return nonzero;
}

template <class T>
Result<size_t> convertFloats(const void* data, size_t first, size_t n, std::vector<Label>& out, const std::string& path) {
  const T* src = static_cast<const T*>(data);
  size_t nonzero = 0;
  for (size_t i = 0; i < n; ++i) {
    T v = src[i];
    if (!std::isfinite(v)) v = 0;  // as libnifti's own loader does: NaN and infinity read as 0
    if (!(v >= T(std::numeric_limits<Label>::min()) && v <= T(std::numeric_limits<Label>::max())) ||
        std::trunc(v) != v)
      return makeError(path, "floating-point labels must be whole numbers in the 16-bit range; voxel " +
                                 std::to_string(first + i) + " holds " + num(double(v)));
    out[first + i] = static_cast<Label>(v);
    nonzero += v != 0;
  }
  return nonzero;
}

Result<size_t> convertSlab(int datatype, const void* data, size_t first, size_t n, std::vector<Label>& out,
                           const std::string& path) {
  switch (datatype) {
    case DT_UINT8: return convertInts<uint8_t>(data, first, n, out, path);
    case DT_INT8: return convertInts<int8_t>(data, first, n, out, path);
    case DT_INT16: return convertInts<int16_t>(data, first, n, out, path);
    case DT_UINT16: return convertInts<uint16_t>(data, first, n, out, path);
    case DT_INT32: return convertInts<int32_t>(data, first, n, out, path);
    case DT_UINT32: return convertInts<uint32_t>(data, first, n, out, path);
    case DT_FLOAT32: return convertFloats<float>(data, first, n, out, path);
    case DT_FLOAT64: return convertFloats<double>(data, first, n, out, path);
    default: return makeError(path, "unsupported datatype " + datatypeName(datatype));
  }
}

// Streams the voxels from the file into `out` one slab at a time, so that memory is the labels
// alone: an int32 file never needs its whole stored data in memory beside them. A short read means
// the file (or its compressed stream) ended early. Returns how many labels are not 0.
// `convert(data, first, n)` takes each slab of n stored voxels (in native byte order) starting at
// voxel `first`, and returns how many were not 0.
using SlabSink = std::function<Result<size_t>(const void* data, size_t first, size_t n)>;

Result<size_t> readVoxels(const nifti_image& nim, bool gz, uint64_t data_bytes, size_t voxels, const SlabSink& convert,
                          const std::string& path) {
  const auto truncated = [&] {
    return makeError(path, std::string("truncated or corrupt") + (gz ? " compressed" : "") +
                               " voxel data: could not read the " + std::to_string(data_bytes) +
                               " bytes the header promises");
  };
  znzFile fp = znzopen(nim.iname, "rb", gz ? 1 : 0);
  if (znz_isnull(fp)) return makeError(path, "cannot open the voxel data");
  const struct Closer {
    znzFile& f;
    ~Closer() { znzclose(f); }
  } closer{fp};
  if (znzseek(fp, znz_off_t(nim.iname_offset), SEEK_SET) < 0) return truncated();
  const size_t bpv = size_t(nim.nbyper);
  constexpr size_t kSlabBytes = size_t{1} << 20;  // 1 MiB, a whole number of voxels of any type [B]
  std::vector<uint8_t> slab(kSlabBytes);
  const bool swap = nim.byteorder != nifti_short_order() && bpv > 1;
  size_t nonzero = 0;
  for (size_t first = 0; first < voxels;) {
    const size_t n = std::min(voxels - first, kSlabBytes / bpv);
    if (znzread(slab.data(), 1, n * bpv, fp) != n * bpv) return truncated();
    if (swap) nifti_swap_Nbytes(int64_t(n), int(bpv), slab.data());
    Result<size_t> converted = convert(slab.data(), first, n);
    if (!converted) return converted.error();
    nonzero += *converted;
    first += n;
  }
  return nonzero;
}

// A NIfTI file whose header has passed both checks, before any voxel is read.
struct OpenedNifti {
  HeaderInfo info;
  CheckedHeader checked;
  NimPtr nim;
  bool gz = false;
};

Result<OpenedNifti> openNifti(const std::string& path, const NiftiReadLimits& limits, bool grey) {
  silenceNifti();
  const char* what = grey ? "a NIfTI grey-value volume" : "a NIfTI label volume";
  // libnifti would quietly try sibling names ("a.nii" -> "a.nii.gz"), so the exact path is checked first.
  // libnifti opens the file itself, so a FIFO or a device is refused here, before it can block.
  Result<uint64_t> size = regularFileSize(path);
  if (!size) return size.error();
  if (*size == 0) return makeError(path, "empty file, not a NIfTI image");
  const bool gz = isGzipName(path);
  if (!endsWith(path, ".nii") && !gz) {
    // A mesh or a volume named on the wrong option says what it is.
    Result<std::vector<uint8_t>> head = readFileHead(path, kFileKindHeadBytes);
    if (head)
      if (auto other = refuseOtherKind(*head, FileKind::Nifti1, path, std::string(what) + " (.nii or .nii.gz)"))
        return *other;
    return makeError(path, "not a NIfTI file name (expected .nii or .nii.gz)");
  }
  const uint64_t file_bytes = *size;

  // 1. The raw header alone, checked before anything is allocated for voxels.
  int version = 0;
  std::unique_ptr<void, FreeDeleter> raw(nifti_read_header(path.c_str(), &version, 0));
  if (!raw || (version != 1 && version != 2)) {
    if (startsLikeNifti(path, gz))
      return makeError(path, "truncated or corrupt header (it starts like NIfTI but cannot be read whole)");
    Result<std::vector<uint8_t>> head = readFileHead(path, kFileKindHeadBytes);
    if (head)
      if (auto other = refuseOtherKind(*head, gz ? FileKind::Gzip : FileKind::Nifti1, path, what))
        return *other;
    return makeError(path, "not a NIfTI file (no valid NIfTI-1 or NIfTI-2 header)");
  }
  OpenedNifti opened;
  opened.gz = gz;
  opened.info = headerInfo(raw.get(), version);
  raw.reset();
  Result<CheckedHeader> checked = checkHeader(opened.info, path, limits, grey);
  if (!checked) return checked.error();
  opened.checked = *checked;
  const uint64_t needed = uint64_t(opened.info.vox_offset) + checked->data_bytes;
  if (!gz && file_bytes < needed)
    return makeError(path, "truncated: the header promises " + std::to_string(needed) + " bytes, the file has " +
                               std::to_string(file_bytes));
  constexpr uint64_t kMaxDeflateRatio = 1100;  // deflate's best case is about 1032:1
  if (gz && needed / kMaxDeflateRatio > file_bytes)
    return makeError(path, "truncated: " + std::to_string(file_bytes) + " compressed bytes cannot hold the " +
                               std::to_string(needed) + " bytes the header promises");

  // 2. libnifti's own view of the header (and extensions), cross-checked against ours.
  opened.nim.reset(nifti_image_read(path.c_str(), 0));
  const nifti_image* nim = opened.nim.get();
  if (!nim) return makeError(path, "not a valid NIfTI file (libnifti rejected the header or its extensions)");
  if (nim->nx != checked->dims[0] || nim->ny != checked->dims[1] || nim->nz != checked->dims[2] ||
      nim->nvox != checked->voxels || nim->datatype != opened.info.datatype ||
      nim->nbyper != checked->bytes_per_voxel)
    return makeError(path, "inconsistent NIfTI header (libnifti reads other dimensions or datatype)");
  return opened;
}

// Geometry in mm: pitch from pixdim, placement from sform, else qform, else the pitch alone.
Status readGeometry(const OpenedNifti& opened, std::array<double, 3>& pitch, std::array<double, 12>& scanner,
                    const std::string& path) {
  const HeaderInfo& info = opened.info;
  const nifti_image& nim = *opened.nim;
  const double unit = mmPerUnit(info.xyzt_units);
  for (size_t a = 0; a < 3; ++a) pitch[a] = info.pixdim[a + 1] * unit;
  if (nim.sform_code > 0) {
    scanner = fromDmat44(nim.sto_xyz, unit);
  } else if (nim.qform_code > 0) {
    scanner = fromDmat44(nim.qto_xyz, unit);
  } else {
    scanner = {};
    for (size_t a = 0; a < 3; ++a) scanner[5 * a] = pitch[a];
  }
  for (double v : scanner)
    if (!std::isfinite(v)) return makeError(path, "scanner matrix (sform/qform) holds a non-finite value");
  const double p3 = pitch[0] * pitch[1] * pitch[2];
  if (!(std::fabs(det3(scanner)) > 1e-12 * p3)) return makeError(path, "scanner matrix (sform/qform) is singular");
  return Ok{};
}

// Stored grey values into floats with the file's scaling (scl_slope 0 means none).
template <class T>
size_t convertGrey(const void* data, size_t first, size_t n, double slope, double inter, std::vector<float>& out) {
  const T* src = static_cast<const T*>(data);
  size_t nonzero = 0;
  for (size_t i = 0; i < n; ++i) {
    double v = double(src[i]);
    if (!std::isfinite(v)) v = 0;  // as libnifti's own loader does
    const float f = float(v * slope + inter);
    out[first + i] = std::isfinite(f) ? f : 0.0f;
    nonzero += f != 0.0f;
  }
  return nonzero;
}

}  // namespace

// ---- 4. readNiftiLabels and readNiftiGrey -----------------------------------------------------

Result<LabelImage> readNiftiLabels(const std::string& path, const NiftiReadLimits& limits) {
  Result<OpenedNifti> opened = openNifti(path, limits, false);
  if (!opened) return opened.error();
  const CheckedHeader& checked = opened->checked;
  // 3. The voxels, streamed into the labels: the labels are what stays in memory, so they are what
  // the input budget bounds (checked before they are allocated).
  const uint64_t label_bytes = uint64_t(checked.voxels) * sizeof(Label);
  if (label_bytes > limits.max_label_bytes)
    return makeError(path, limitExceeded("labels of " + std::to_string(checked.voxels) + " voxels (" +
                                             std::to_string(label_bytes) + " bytes)",
                                         limits.max_label_bytes));
  LabelImage image;
  image.dims = checked.dims;
  image.labels.resize(size_t(checked.voxels));
  const int datatype = opened->info.datatype;
  Result<size_t> nonzero = readVoxels(
      *opened->nim, opened->gz, checked.data_bytes, image.labels.size(),
      [&](const void* data, size_t first, size_t n) { return convertSlab(datatype, data, first, n, image.labels, path); },
      path);
  if (!nonzero) return nonzero.error();
  if (*nonzero == 0) return makeError(path, "holds no tooth: every voxel is 0");
  if (Status s = readGeometry(*opened, image.pitch_mm, image.scanner_from_voxel, path); !s) return s.error();
  return image;
}

Result<GreyImage> readNiftiGrey(const std::string& path, const NiftiReadLimits& limits) {
  Result<OpenedNifti> opened = openNifti(path, limits, true);
  if (!opened) return opened.error();
  const CheckedHeader& checked = opened->checked;
  const uint64_t float_bytes = uint64_t(checked.voxels) * sizeof(float);
  if (float_bytes > limits.max_label_bytes * 2)
    return makeError(path, limitExceeded("grey values of " + std::to_string(checked.voxels) + " voxels (" +
                                             std::to_string(float_bytes) + " bytes as float)",
                                         limits.max_label_bytes * 2));
  // The data is read in slabs, so nothing but the floats is held at full size.
  if (limits.approve)
    if (Status s = limits.approve(uint64_t(checked.voxels), 0); !s) return s.error();
  GreyImage image;
  image.dims = checked.dims;
  image.values.resize(size_t(checked.voxels));
  const HeaderInfo& h = opened->info;
  const bool scaled = std::isfinite(h.scl_slope) && h.scl_slope != 0.0;
  const double slope = scaled ? h.scl_slope : 1.0, inter = scaled && std::isfinite(h.scl_inter) ? h.scl_inter : 0.0;
  const auto convert = [&](const void* data, size_t first, size_t n) -> Result<size_t> {
    switch (h.datatype) {
      case DT_UINT8: return convertGrey<uint8_t>(data, first, n, slope, inter, image.values);
      case DT_INT8: return convertGrey<int8_t>(data, first, n, slope, inter, image.values);
      case DT_INT16: return convertGrey<int16_t>(data, first, n, slope, inter, image.values);
      case DT_UINT16: return convertGrey<uint16_t>(data, first, n, slope, inter, image.values);
      case DT_INT32: return convertGrey<int32_t>(data, first, n, slope, inter, image.values);
      case DT_UINT32: return convertGrey<uint32_t>(data, first, n, slope, inter, image.values);
      case DT_FLOAT32: return convertGrey<float>(data, first, n, slope, inter, image.values);
      case DT_FLOAT64: return convertGrey<double>(data, first, n, slope, inter, image.values);
      default: return makeError(path, "unsupported datatype " + datatypeName(h.datatype));
    }
  };
  Result<size_t> nonzero = readVoxels(*opened->nim, opened->gz, checked.data_bytes, image.values.size(), convert, path);
  if (!nonzero) return nonzero.error();
  if (*nonzero == 0) return makeError(path, "holds no scan: every voxel is 0");
  if (Status s = readGeometry(*opened, image.pitch_mm, image.scanner_from_voxel, path); !s) return s.error();
  image.unit = GreyUnit::Raw;
  return image;
}

// ---- 5. writeNiftiLabels --------------------------------------------------------------------

Status writeNiftiLabels(const std::string& path, const LabelImage& image) {
  silenceNifti();
  if (!endsWith(path, ".nii") && !isGzipName(path))
    return makeError(path, "output must end in .nii or .nii.gz");
  for (int32_t d : image.dims)
    if (d <= 0) return makeError(path, "cannot write an image with no voxels");
  if (image.labels.size() != size_t(image.voxelCount()))
    return makeError(path, "label count does not match the dimensions");
  for (double p : image.pitch_mm)
    if (!std::isfinite(p) || p <= 0.0) return makeError(path, "invalid voxel size " + num(p));
  for (double v : image.scanner_from_voxel)
    if (!std::isfinite(v)) return makeError(path, "scanner matrix holds a non-finite value");

  // uint8 voxels, the smallest type every viewer reads; refuse codes that would wrap.
  std::unique_ptr<uint8_t, FreeDeleter> bytes(static_cast<uint8_t*>(std::malloc(image.labels.size())));
  if (!bytes) return makeError(path, "out of memory for " + std::to_string(image.labels.size()) + " voxels");
  for (size_t i = 0; i < image.labels.size(); ++i) {
    const Label v = image.labels[i];
    if (v < 0 || v > 255)
      return makeError(path, "label " + std::to_string(v) + " does not fit the uint8 labels of the file");
    bytes.get()[i] = static_cast<uint8_t>(v);
  }

  const int64_t dims[8] = {3, image.dims[0], image.dims[1], image.dims[2], 1, 1, 1, 1};
  NimPtr nim(nifti_make_new_nim(dims, DT_UINT8, 0));
  if (!nim) return makeError(path, "cannot build the NIfTI header");
  nim->nifti_type = NIFTI_FTYPE_NIFTI1_1;
  nim->dx = nim->pixdim[1] = image.pitch_mm[0];
  nim->dy = nim->pixdim[2] = image.pitch_mm[1];
  nim->dz = nim->pixdim[3] = image.pitch_mm[2];
  nim->xyz_units = NIFTI_UNITS_MM;
  nim->time_units = NIFTI_UNITS_UNKNOWN;
  nim->scl_slope = 0.0;  // no scaling
  nim->scl_inter = 0.0;
  nifti_dmat44 m{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m.m[r][c] = image.scanner_from_voxel[size_t(4 * r + c)];
  m.m[3][3] = 1.0;
  nim->sform_code = NIFTI_XFORM_SCANNER_ANAT;
  nim->sto_xyz = m;
  nim->sto_ijk = nifti_dmat44_inverse(m);
  // The qform can only hold a rotation (with one flip) times the pitch; libnifti projects the
  // matrix onto the nearest such one, which is exact for the axis-aligned and flipped frames we write.
  nim->qform_code = NIFTI_XFORM_SCANNER_ANAT;
  double qdx = 0, qdy = 0, qdz = 0;
  nifti_dmat44_to_quatern(m, &nim->quatern_b, &nim->quatern_c, &nim->quatern_d, &nim->qoffset_x,
                          &nim->qoffset_y, &nim->qoffset_z, &qdx, &qdy, &qdz, &nim->qfac);
  nim->qto_xyz = nifti_quatern_to_dmat44(nim->quatern_b, nim->quatern_c, nim->quatern_d, nim->qoffset_x,
                                         nim->qoffset_y, nim->qoffset_z, nim->dx, nim->dy, nim->dz, nim->qfac);
  nim->qto_ijk = nifti_dmat44_inverse(nim->qto_xyz);

  const std::string temp = temporarySibling(path);
  if (nifti_set_filenames(nim.get(), temp.c_str(), 0, 1) != 0) return makeError(path, "cannot name the output file");
  nim->data = bytes.get();
  // Write data and leave the file open, so that the close (which flushes gzip) can be checked too.
  znzFile fp = nifti_image_write_hdr_img(nim.get(), 3, "wb");
  nim->data = nullptr;  // the buffer stays ours; nifti_image_free must not free it
  bool written = fp != nullptr && !znz_isnull(fp);
  if (fp != nullptr) written = (Xznzclose(&fp) == 0) && written;
  if (!written) {
    discardTemporary(temp);
    return makeError(path, "cannot write the NIfTI file");
  }
  // An uncompressed file has a size we can check; a short one means the disk filled up.
  if (!isGzipName(path)) {
    struct stat st {};
    const uint64_t expected = 352 + image.labels.size();
    if (::stat(temp.c_str(), &st) != 0 || uint64_t(st.st_size) < expected) {
      discardTemporary(temp);
      return makeError(path, "write incomplete (disk full?)");
    }
  }
  return commitTemporary(temp, path);
}

}  // namespace dentsim
