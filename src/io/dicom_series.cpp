// Reading DICOM series through GDCM into a GreyImage (headers first, then pixels into their place), and writing one back.
//
// Contents
//   1. Header values as text, vectors and their checks
//   2. One file's header (SliceHeader)
//   3. Pixels of one file into floats
//   4. readDicomFile
//   5. readDicomSeries: group, check, sort, place
//   6. writeDicomSeries
#include "io/dicom_series.h"

#include <gdcmDataElement.h>
#include <gdcmDataSet.h>
#include <gdcmExplicitDataElement.h>
#include <gdcmImplicitDataElement.h>
#include <gdcmFile.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmMediaStorage.h>
#include <gdcmPixelFormat.h>
#include <gdcmReader.h>
#include <gdcmSequenceOfFragments.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmStringFilter.h>
#include <gdcmTrace.h>
#include <gdcmTransferSyntax.h>
#include <gdcmUIDGenerator.h>
#include <gdcmUIDs.h>
#include <gdcmWriter.h>

#include <algorithm>
#include <functional>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>

#include "io/atomic_file.h"
#include "io/sandboxed_read.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
using Vec = std::array<double, 3>;

// GDCM reports problems on std::cerr by default; dentsim's errors are its own one-line messages.
void quietGdcm() {
  static const bool once = [] {
    gdcm::Trace::SetDebug(false);
    gdcm::Trace::SetWarning(false);
    gdcm::Trace::SetError(false);
    return true;
  }();
  (void)once;
}

// GDCM as Debian builds it keeps its assertions, and some damaged files reach one (a file meta
// header cut short aborts inside GDCM); others declare an element of gigabytes, which GDCM allocates
// and fills before it finds the file too short. So every read runs first in a child
// (io/sandboxed_read.h) whose data segment may grow by the budget and 256 MB more, and no further.
//
// Its time limits scale with the bytes it reads: GDCM that loops or grows exponentially on a
// crafted file (as its length calculation does with nesting, section 2) ends as a line, not a hang.
// Generous: 30 s, and 2 s a MiB besides, of processor time, which decodes any compression GDCM
// reads; the parent waits twice that, and 30 s more, on a busy machine.
Status readInChild(const std::string& where, uint64_t budget, uint64_t input_bytes,
                   const std::function<Status(SandboxNote&)>& work) {
  SandboxLimits limits;
  limits.data_growth_bytes = budget + (uint64_t{256} << 20);
  limits.cpu_s = 30 + 2 * (input_bytes >> 20);
  limits.wall_s = 2 * limits.cpu_s + 30;
  const SandboxWords words{"GDCM", "deeply nested, or damaged", "truncated or damaged DICOM file: GDCM stops on it"};
  return runSandboxed(where, limits, work, words);
}

// ---- 1. Header values ------------------------------------------------------------------------
const gdcm::Tag kRows(0x0028, 0x0010), kColumns(0x0028, 0x0011), kPixelSpacing(0x0028, 0x0030),
    kPosition(0x0020, 0x0032), kOrientation(0x0020, 0x0037), kSeriesUid(0x0020, 0x000e),
    kModality(0x0008, 0x0060), kManufacturer(0x0008, 0x0070), kModel(0x0008, 0x1090),
    kDescription(0x0008, 0x103e), kRescaleType(0x0028, 0x1054), kFrames(0x0028, 0x0008),
    kGantryTilt(0x0018, 0x1120), kSamples(0x0028, 0x0002), kSliceThickness(0x0018, 0x0050),
    kBitsAllocated(0x0028, 0x0100), kPixelData(0x7fe0, 0x0010);

// What a scan's geometry may be. A CT table travels 2 m at most and scanners put the origin near
// the gantry's centre, so 10 m from it is no patient; a pixel or a slice step of 100 mm is coarser
// than any scout, while a tooth needs tenths of a millimetre. Beyond these the numbers are forged
// or broken, and a volume made from them (kilometres wide) is one no later stage could read.
constexpr double kMaxPositionMm = 10000.0;  // |each Image Position (Patient) coordinate| [mm]
constexpr double kMaxSpacingMm = 100.0;     // Pixel Spacing, slice step and Slice Thickness [mm]

std::string trimmed(std::string s) {
  const auto keep = [](char c) { return c != ' ' && c != '\0' && c != '\r' && c != '\n' && c != '\t'; };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), keep));
  s.erase(std::find_if(s.rbegin(), s.rend(), keep).base(), s.end());
  return s;
}

// A header value as text, or empty when the element is missing. Control characters become '?', so
// that a value quoted in an error cannot break its one line; 200 characters at most.
std::string text(const gdcm::File& file, const gdcm::Tag& tag) {
  if (!file.GetDataSet().FindDataElement(tag)) return {};
  gdcm::StringFilter sf;
  sf.SetFile(file);
  std::string s = trimmed(sf.ToString(tag));
  if (s.size() > 200) s.resize(200);
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return s;
}

// Backslash-separated decimal numbers; false unless there are exactly `n`, all finite.
bool numbers(const std::string& s, size_t n, double* out) {
  std::stringstream in(s);
  std::string item;
  size_t count = 0;
  while (std::getline(in, item, '\\')) {
    if (count == n) return false;
    item = trimmed(item);
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(v)) return false;
    out[count++] = v;
  }
  return count == n;
}

Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }

std::string mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

bool hasDicomPreamble(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[132] = {};
  if (!in.read(head, sizeof head)) return false;
  return std::memcmp(head + 128, "DICM", 4) == 0;
}

// ---- 2. SliceHeader --------------------------------------------------------------------------
struct SliceHeader {
  std::string path;
  std::string series_uid, modality, manufacturer, model, description, rescale_type, transfer_syntax;
  int32_t rows = 0, columns = 0, frames = 1, samples = 1;
  std::array<double, 2> spacing{0, 0};  // between rows (along j), between columns (along i) [mm]
  std::array<double, 6> orientation{1, 0, 0, 0, 1, 0};
  Vec position{0, 0, 0};
  bool has_position = false, has_orientation = false, has_spacing = false;
  double gantry_tilt = 0.0;      // degrees
  double slice_thickness = 0.0;  // [mm], 0 when absent
  int32_t bits_allocated = 0;    // (0028,0100); 0 when absent
  // The Pixel Data element as the header gives it, so that pixels the file does not hold are
  // refused before a buffer is made for them (checkPixelsInFile).
  bool has_pixel_data = false;
  bool encapsulated = false;        // compressed: fragments of undefined total length
  uint64_t pixel_data_bytes = 0;    // native: the element's length [B]
  uint64_t pixel_fragments = 0;     // encapsulated: fragments after the offset table
};

enum class HeaderKind { Image, NotImage, NotDicom };

// GDCM's length of a data set (the truncation check in decodePixels asks for it) grows about
// sixfold with each level of sequences nested in sequences: 8 levels take milliseconds, 12 take
// seconds and 100 never end. Scanners nest their images' sequences 2 to 4 deep, so an image whose
// sequences nest deeper than this is refused when its header is read, before any length is asked.
constexpr int kMaxSequenceDepth = 8;

// The deepest nesting of sequences in `ds` (a sequence at the top is 1), counted no further than
// `limit` + 1, so that a file nested thousands deep costs no more than one at the limit.
int sequenceDepth(const gdcm::DataSet& ds, int limit) {
  int deepest = 0;
  for (const gdcm::DataElement& de : ds.GetDES()) {
    const auto* sq = de.IsEmpty() ? nullptr : dynamic_cast<const gdcm::SequenceOfItems*>(&de.GetValue());
    if (!sq) continue;
    deepest = std::max(deepest, 1);
    if (limit <= 0) return 1;
    for (size_t i = 1; i <= sq->GetNumberOfItems() && deepest <= limit; ++i)
      deepest = std::max(deepest, 1 + sequenceDepth(sq->GetItem(i).GetNestedDataSet(), limit - 1));
    if (deepest > limit) return deepest;
  }
  return deepest;
}

// Reads the header up to the pixel data. A file that claims DICOM and cannot be read is an error.
Result<HeaderKind> readHeader(SandboxNote& note, const std::string& path, SliceHeader& h) {
  note.file(path);
  gdcm::Reader reader;
  reader.SetFileName(path.c_str());
  const bool dicom = hasDicomPreamble(path);
  if (!reader.ReadUpToTag(kPixelData)) {
    if (dicom) return makeError(path, "truncated or damaged DICOM file (its header cannot be read)");
    return HeaderKind::NotDicom;
  }
  const gdcm::File& f = reader.GetFile();
  h.path = path;
  const std::string rows = text(f, kRows), columns = text(f, kColumns);
  if (rows.empty() || columns.empty()) return HeaderKind::NotImage;
  if (sequenceDepth(f.GetDataSet(), kMaxSequenceDepth) > kMaxSequenceDepth)
    return makeError(path, "sequences nested more than " + std::to_string(kMaxSequenceDepth) +
                               " deep; dentsim reads images nested " + std::to_string(kMaxSequenceDepth) + " deep at most");
  double v[6];
  if (!numbers(rows, 1, v) || v[0] < 1 || v[0] > 65535) return makeError(path, "Rows is not a valid size: '" + rows + "'");
  h.rows = int32_t(v[0]);
  if (!numbers(columns, 1, v) || v[0] < 1 || v[0] > 65535)
    return makeError(path, "Columns is not a valid size: '" + columns + "'");
  h.columns = int32_t(v[0]);
  if (const std::string s = text(f, kFrames); !s.empty()) {
    if (!numbers(s, 1, v) || v[0] < 1 || v[0] > 65535) return makeError(path, "Number of Frames is not valid: '" + s + "'");
    h.frames = int32_t(v[0]);
  }
  if (const std::string s = text(f, kSamples); !s.empty() && numbers(s, 1, v)) h.samples = int32_t(v[0]);
  if (const std::string s = text(f, kBitsAllocated); !s.empty() && numbers(s, 1, v) && v[0] >= 1 && v[0] <= 64)
    h.bits_allocated = int32_t(v[0]);
  if (const std::string s = text(f, kPixelSpacing); !s.empty()) {
    if (!numbers(s, 2, v) || !(v[0] > 0) || !(v[1] > 0))
      return makeError(path, "Pixel Spacing is not two positive finite numbers: '" + s + "'");
    if (v[0] > kMaxSpacingMm || v[1] > kMaxSpacingMm)
      return makeError(path, "Pixel Spacing '" + s + "' is beyond " + mm(kMaxSpacingMm) + " mm: no scan of a tooth");
    h.spacing = {v[0], v[1]};
    h.has_spacing = true;
  }
  if (const std::string s = text(f, kOrientation); !s.empty()) {
    if (!numbers(s, 6, v)) return makeError(path, "Image Orientation (Patient) is not six numbers: '" + s + "'");
    std::copy(v, v + 6, h.orientation.begin());
    const Vec r{v[0], v[1], v[2]}, c{v[3], v[4], v[5]};
    if (std::fabs(norm(r) - 1) > 1e-3 || std::fabs(norm(c) - 1) > 1e-3 || std::fabs(dot(r, c)) > 1e-3)
      return makeError(path, "Image Orientation (Patient) is not two perpendicular unit vectors: '" + s + "'");
    h.has_orientation = true;
  }
  if (const std::string s = text(f, kPosition); !s.empty()) {
    if (!numbers(s, 3, v)) return makeError(path, "Image Position (Patient) is not three finite numbers: '" + s + "'");
    if (std::fabs(v[0]) > kMaxPositionMm || std::fabs(v[1]) > kMaxPositionMm || std::fabs(v[2]) > kMaxPositionMm)
      return makeError(path, "Image Position (Patient) '" + s + "' lies beyond " + mm(kMaxPositionMm) +
                                 " mm of the scanner's origin: no patient is there");
    h.position = {v[0], v[1], v[2]};
    h.has_position = true;
  }
  if (const std::string s = text(f, kGantryTilt); !s.empty() && numbers(s, 1, v)) h.gantry_tilt = v[0];
  if (const std::string s = text(f, kSliceThickness); !s.empty() && numbers(s, 1, v) && v[0] > 0) h.slice_thickness = v[0];
  if (f.GetDataSet().FindDataElement(kPixelData)) {
    const gdcm::DataElement& de = f.GetDataSet().GetDataElement(kPixelData);
    h.has_pixel_data = true;
    if (const gdcm::SequenceOfFragments* frags = de.GetSequenceOfFragments()) {
      h.encapsulated = true;
      h.pixel_fragments = frags->GetNumberOfFragments();
    } else {
      h.pixel_data_bytes = de.GetVL().IsUndefined() ? 0 : uint64_t(uint32_t(de.GetVL()));
    }
  }
  h.series_uid = text(f, kSeriesUid);
  h.modality = text(f, kModality);
  h.manufacturer = text(f, kManufacturer);
  h.model = text(f, kModel);
  h.description = text(f, kDescription);
  h.rescale_type = text(f, kRescaleType);
  const gdcm::TransferSyntax ts = f.GetHeader().GetDataSetTransferSyntax();
  const char* ts_uid = gdcm::TransferSyntax::GetTSString(ts);
  gdcm::UIDs uid;
  h.transfer_syntax = ts_uid && uid.SetFromUID(ts_uid) && uid.GetName() ? std::string(uid.GetName()) + " " + ts_uid
                                                                         : std::string(ts_uid ? ts_uid : "unknown");
  return HeaderKind::Image;
}

GreyUnit unitOf(const SliceHeader& h) {
  if (!h.rescale_type.empty()) return h.rescale_type == "HU" ? GreyUnit::Hounsfield : GreyUnit::Raw;
  return h.modality == "CT" ? GreyUnit::Hounsfield : GreyUnit::Raw;
}

// ---- 3. Pixels -------------------------------------------------------------------------------
template <class T>
void toFloats(const char* bytes, size_t count, int bits_stored, bool is_signed, double slope, double intercept,
              float* out) {
  const bool mask = std::is_integral_v<T> && bits_stored > 0 && bits_stored < int(8 * sizeof(T));
  for (size_t n = 0; n < count; ++n) {
    T raw;
    std::memcpy(&raw, bytes + n * sizeof(T), sizeof(T));
    double value = double(raw);
    if constexpr (std::is_integral_v<T>) {
      if (mask) {
        // Bits above Bits Stored may hold overlays; the stored value is the low bits, sign-extended.
        const int64_t low = int64_t(uint64_t(std::make_unsigned_t<T>(raw)) & ((uint64_t{1} << bits_stored) - 1));
        value = double(is_signed && (low >> (bits_stored - 1)) ? low - (int64_t{1} << bits_stored) : low);
      }
    }
    const float v = float(value * slope + intercept);
    out[n] = std::isfinite(v) ? v : 0.0f;  // as the NIfTI and NRRD readers: NaN and infinity read as 0
  }
}

// Decodes every frame of `path` into `out` (rows * columns * frames floats), applying its rescale.
// `frame_step_mm`, when given, receives GDCM's spacing between frames (0 when it has none).
Status decodePixels(SandboxNote& note, const std::string& path, const SliceHeader& h, float* out, DicomSeriesInfo* info,
                    double* frame_step_mm = nullptr) {
  note.file(path);
  gdcm::ImageReader reader;
  reader.SetFileName(path.c_str());
  if (!reader.Read()) return makeError(path, "truncated or damaged DICOM file (its pixel data cannot be read)");
  const gdcm::Image& image = reader.GetImage();
  const gdcm::PixelFormat pf = image.GetPixelFormat();
  if (pf.GetSamplesPerPixel() != 1)
    return makeError(path, "a colour image (" + std::to_string(pf.GetSamplesPerPixel()) + " samples a pixel), not a scan");
  const uint32_t frames = image.GetNumberOfDimensions() >= 3 ? image.GetDimension(2) : 1;
  if (int32_t(image.GetDimension(0)) != h.columns || int32_t(image.GetDimension(1)) != h.rows ||
      int32_t(frames) != h.frames)
    return makeError(path, "the pixel data's size differs from its header");
  const size_t count = size_t(h.columns) * size_t(h.rows) * frames;
  const unsigned long length = image.GetBufferLength();
  if (length != count * pf.GetPixelSize())
    return makeError(path, "the pixel data holds " + std::to_string(length) + " bytes where " +
                               std::to_string(count * pf.GetPixelSize()) + " are expected");
  // A file shorter than its elements say is cut short, whatever GDCM pads the missing pixels with.
  // A deflated data set's elements measure the inflated stream, not the file; zlib itself refuses
  // that stream cut short (GDCM's read fails above).
  if (!reader.GetFile().GetHeader().GetDataSetTransferSyntax().IsEncoded()) {
    const gdcm::File& file = reader.GetFile();
    const bool implicit = file.GetHeader().GetDataSetTransferSyntax().GetNegociatedType() == gdcm::TransferSyntax::Implicit;
    const uint64_t body = implicit ? uint64_t(file.GetDataSet().GetLength<gdcm::ImplicitDataElement>())
                                   : uint64_t(file.GetDataSet().GetLength<gdcm::ExplicitDataElement>());
    const uint64_t meta = hasDicomPreamble(path) ? uint64_t(file.GetHeader().GetFullLength()) : 0;  // with the preamble
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    if (!ec && size < body + meta)
      return makeError(path, "truncated: " + std::to_string(size) + " bytes where its elements need " +
                                 std::to_string(body + meta));
  }
  std::vector<char> buffer(length);
  if (!image.GetBuffer(buffer.data()))
    return makeError(path, "cannot decode its pixel data (transfer syntax " + h.transfer_syntax +
                               "): truncated, or a compression GDCM cannot read");
  const int bits = pf.GetBitsStored();
  const bool is_signed = pf.GetPixelRepresentation() == 1;
  const double slope = image.GetSlope(), intercept = image.GetIntercept();
  if (!std::isfinite(slope) || !std::isfinite(intercept) || slope == 0.0)
    return makeError(path, "rescale slope and intercept are not usable numbers");
  switch (pf.GetScalarType()) {
    case gdcm::PixelFormat::UINT8: toFloats<uint8_t>(buffer.data(), count, bits, false, slope, intercept, out); break;
    case gdcm::PixelFormat::INT8: toFloats<int8_t>(buffer.data(), count, bits, true, slope, intercept, out); break;
    case gdcm::PixelFormat::UINT12:
    case gdcm::PixelFormat::UINT16: toFloats<uint16_t>(buffer.data(), count, bits, false, slope, intercept, out); break;
    case gdcm::PixelFormat::INT12:
    case gdcm::PixelFormat::INT16: toFloats<int16_t>(buffer.data(), count, bits, is_signed, slope, intercept, out); break;
    case gdcm::PixelFormat::UINT32: toFloats<uint32_t>(buffer.data(), count, bits, false, slope, intercept, out); break;
    case gdcm::PixelFormat::INT32: toFloats<int32_t>(buffer.data(), count, bits, is_signed, slope, intercept, out); break;
    case gdcm::PixelFormat::FLOAT32: toFloats<float>(buffer.data(), count, 0, true, slope, intercept, out); break;
    default:
      return makeError(path, std::string("pixel type ") + pf.GetScalarTypeAsString() + " is not a scan's grey value");
  }
  if (frame_step_mm) *frame_step_mm = image.GetNumberOfDimensions() >= 3 ? image.GetSpacing(2) : 0.0;
  if (info) {
    info->rescale_slope = slope;
    info->rescale_intercept = intercept;
    info->bits_stored = bits;
    info->signed_pixels = is_signed;
    info->transfer_syntax = h.transfer_syntax;
  }
  return Ok{};
}

// Rows, Columns and Number of Frames are the file's word for how many pixels it holds; a forged
// Rows of 65,535 would otherwise make a volume of pixels the file never held (GDCM pads what is
// missing). Checked from the header, before any buffer is made for the pixels. A native Pixel Data
// element must hold every sample (Bits Allocated each, a byte when absent); a compressed one must
// hold a fragment a frame at least (a fragment never holds two frames), and its decoded size is
// checked against the header again after decoding (decodePixels).
Status checkPixelsInFile(const SliceHeader& h) {
  if (!h.has_pixel_data) return makeError(h.path, "an image without a Pixel Data element");
  if (h.encapsulated) {
    if (h.pixel_fragments < uint64_t(h.frames))
      return makeError(h.path, "its header says " + std::to_string(h.frames) + (h.frames == 1 ? " frame" : " frames") +
                                   " but its compressed Pixel Data holds " + std::to_string(h.pixel_fragments) +
                                   (h.pixel_fragments == 1 ? " fragment" : " fragments"));
    return Ok{};
  }
  const uint64_t bits = uint64_t(h.rows) * uint64_t(h.columns) * uint64_t(h.frames) * uint64_t(std::max(h.samples, 1)) *
                        uint64_t(h.bits_allocated > 0 ? h.bits_allocated : 8);
  const uint64_t need = (bits + 7) / 8;
  if (h.pixel_data_bytes < need)
    return makeError(h.path, "Rows x Columns x frames x samples (" + std::to_string(h.rows) + " x " +
                                 std::to_string(h.columns) + " x " + std::to_string(h.frames) + " x " +
                                 std::to_string(std::max(h.samples, 1)) + ") need " + std::to_string(need) +
                                 " bytes of pixels but its Pixel Data holds " + std::to_string(h.pixel_data_bytes));
  return Ok{};
}

Status checkBudget(const std::string& where, uint64_t voxels, uint64_t max_bytes) {
  if (voxels > max_bytes / sizeof(float))
    return makeError(where, limitExceeded("a volume of " + std::to_string(voxels) + " voxels as float", max_bytes));
  return Ok{};
}

void copyDescription(const SliceHeader& h, GreyImage& image) {
  image.unit = unitOf(h);
  image.modality = h.modality;
  image.manufacturer = h.manufacturer;
  image.model = h.model;
  image.description = h.description;
}

// The scanner matrix of a volume whose slices start at `origin` and step by `step` (a vector) [mm].
std::array<double, 12> scannerMatrix(const SliceHeader& h, const Vec& origin, const Vec& step) {
  const Vec r{h.orientation[0], h.orientation[1], h.orientation[2]};
  const Vec c{h.orientation[3], h.orientation[4], h.orientation[5]};
  std::array<double, 12> m{};
  for (int row = 0; row < 3; ++row) {
    m[4 * row + 0] = r[row] * h.spacing[1];  // along i: the distance between columns
    m[4 * row + 1] = c[row] * h.spacing[0];  // along j: the distance between rows
    m[4 * row + 2] = step[row];
    m[4 * row + 3] = origin[row];
  }
  return m;
}

// ---- 4. readDicomFile ------------------------------------------------------------------------
Result<GreyImage> readOneFile(SandboxNote& note, const std::string& path, uint64_t max_bytes, DicomSeriesInfo* info,
                              const ScanReadApproval& approve = {}) {
  SliceHeader h;
  Result<HeaderKind> kind = readHeader(note, path, h);
  if (!kind) return kind.error();
  if (*kind == HeaderKind::NotDicom) return makeError(path, "not a DICOM file");
  if (*kind == HeaderKind::NotImage) return makeError(path, "a DICOM file without an image (no Rows and Columns)");
  if (h.samples != 1) return makeError(path, "a colour image (" + std::to_string(h.samples) + " samples a pixel), not a scan");
  if (Status s = checkPixelsInFile(h); !s) return s.error();
  const uint64_t voxels = uint64_t(h.rows) * uint64_t(h.columns) * uint64_t(h.frames);
  if (Status s = checkBudget(path, voxels, max_bytes); !s) return s.error();
  // GDCM holds a multi-frame file's whole pixel data beside the floats.
  if (approve)
    if (Status s = approve(voxels, uint32_t(std::max(1, h.bits_allocated / 8))); !s) return s.error();
  GreyImage image;
  image.dims = {h.columns, h.rows, h.frames};
  image.values.resize(voxels);
  double frame_step = 0.0;
  if (Status s = decodePixels(note, path, h, image.values.data(), info, &frame_step); !s) return s.error();
  copyDescription(h, image);
  if (!h.has_spacing) h.spacing = {1.0, 1.0};
  // A multi-frame file's frames step along the normal by GDCM's spacing (from its functional groups
  // or Spacing Between Slices); one slice is as thick as it says.
  const Vec r{h.orientation[0], h.orientation[1], h.orientation[2]};
  const Vec c{h.orientation[3], h.orientation[4], h.orientation[5]};
  const Vec n = cross(r, c);
  double dz = h.slice_thickness > 0 ? h.slice_thickness : 1.0;
  if (h.frames > 1 && frame_step > 0) dz = frame_step;
  if (dz > kMaxSpacingMm)
    return makeError(path, "its slice step (Slice Thickness or the frames' spacing) of " + mm(dz) + " mm is beyond " +
                               mm(kMaxSpacingMm) + " mm: no scan of a tooth");
  image.pitch_mm = {h.spacing[1], h.spacing[0], dz};
  image.scanner_from_voxel = scannerMatrix(h, h.position, {n[0] * dz, n[1] * dz, n[2] * dz});
  if (info) {
    info->series_uid = h.series_uid;
    info->files = 1;
    info->slice_spacing_mm = dz;
  }
  return image;
}

// ---- 5. readDicomSeries ----------------------------------------------------------------------
std::string seriesList(const std::map<std::string, std::vector<SliceHeader>>& groups) {
  std::string list;
  for (const auto& [uid, slices] : groups) {
    if (!list.empty()) list += "; ";
    list += (uid.empty() ? std::string("(no Series Instance UID)") : uid) + " with " + std::to_string(slices.size()) +
            (slices.size() == 1 ? " file" : " files");
    if (!slices.front().description.empty()) list += " '" + slices.front().description + "'";
  }
  return list;
}

// Every slice of a series must be cut from one grid.
Status checkSameGrid(const std::string& where, const std::vector<SliceHeader>& slices) {
  const SliceHeader& a = slices.front();
  for (const SliceHeader& b : slices) {
    if (b.rows != a.rows || b.columns != a.columns)
      return makeError(where, "mixed series: " + fs::path(a.path).filename().string() + " is " +
                                  std::to_string(a.columns) + " x " + std::to_string(a.rows) + " pixels but " +
                                  fs::path(b.path).filename().string() + " is " + std::to_string(b.columns) + " x " +
                                  std::to_string(b.rows));
    if (b.has_spacing != a.has_spacing || std::fabs(b.spacing[0] - a.spacing[0]) > 1e-4 * a.spacing[0] ||
        std::fabs(b.spacing[1] - a.spacing[1]) > 1e-4 * a.spacing[1])
      return makeError(where, "mixed series: " + fs::path(b.path).filename().string() +
                                  " has another pixel spacing than " + fs::path(a.path).filename().string());
    for (int q = 0; q < 6; ++q)
      if (std::fabs(b.orientation[q] - a.orientation[q]) > 1e-4)
        return makeError(where, "mixed series: " + fs::path(b.path).filename().string() +
                                    " is oriented differently from " + fs::path(a.path).filename().string());
    if (b.frames != 1) return makeError(where, "mixed series: " + fs::path(b.path).filename().string() +
                                                   " is a multi-frame file among single slices");
    if (b.samples != 1) return makeError(b.path, "a colour image, not a scan");
  }
  return Ok{};
}

// One series is one kind of scan in one unit: an MR or unlabelled slice among CT slices would be
// read as Hounsfield units, and a slice in other units (Rescale Type) would be scaled wrongly.
std::string countsOf(const std::vector<SliceHeader>& slices, std::string SliceHeader::*field, const char* absent) {
  std::map<std::string, int> counts;
  for (const SliceHeader& h : slices) ++counts[h.*field];
  std::string list;
  size_t listed = 0;
  for (const auto& [value, n] : counts) {
    if (listed++ == 4) return list + " and " + std::to_string(counts.size() - 4) + " more";  // a forged series stays one short line
    list += (list.empty() ? "" : ", ") + (value.empty() ? std::string(absent) : value) + " (" + std::to_string(n) +
            (n == 1 ? " file)" : " files)");
  }
  return list;
}

Status checkOneModality(const std::string& where, const std::vector<SliceHeader>& slices) {
  const SliceHeader& a = slices.front();
  for (const SliceHeader& b : slices) {
    if (b.modality != a.modality)
      return makeError(where, "mixed series: its slices are of more than one modality: " +
                                  countsOf(slices, &SliceHeader::modality, "no Modality"));
  }
  for (const SliceHeader& b : slices) {
    if (b.rescale_type != a.rescale_type)
      return makeError(where, "mixed series: its slices are in more than one unit (Rescale Type): " +
                                  countsOf(slices, &SliceHeader::rescale_type, "no Rescale Type"));
  }
  return Ok{};
}

// The regular files below `dir`, sorted. Only regular files: a FIFO or a device among the slices
// would block the first read of it, and links to folders are not followed, so a link back up the
// tree cannot loop. A scanner's series holds thousands of files at most; more is not a series.
constexpr size_t kMaxSeriesFiles = 100000;

Result<std::vector<std::string>> seriesFiles(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (!it->is_regular_file(type_ec)) continue;
    if (files.size() == kMaxSeriesFiles)
      return makeError(dir, "over " + std::to_string(kMaxSeriesFiles) + " files below it; give the series' own folder");
    files.push_back(it->path().string());
  }
  if (ec) return makeError(dir, "cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

Result<GreyImage> readSeries(SandboxNote& note, const std::string& path, const DicomReadOptions& options, Interrupter& interrupter,
                             DicomSeriesInfo* info) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return makeError(path, "no such file or folder");
  if (fs::is_regular_file(path, ec)) {
    Result<GreyImage> one = readOneFile(note, path, options.max_bytes, info, options.approve);
    if (one && one->dims[2] < 2) return makeError(path, "one slice is not a volume; give the folder of the series");
    return one;
  }
  if (!fs::is_directory(path, ec)) return makeError(path, "neither a folder of DICOM files nor a file");

  Result<std::vector<std::string>> listed = seriesFiles(path);
  if (!listed) return listed.error();
  const std::vector<std::string>& files = *listed;
  interrupter.start("reading DICOM headers");
  std::map<std::string, std::vector<SliceHeader>> groups;
  for (size_t n = 0; n < files.size(); ++n) {
    SliceHeader h;
    Result<HeaderKind> kind = readHeader(note, files[n], h);
    if (!kind) return kind.error();
    if (*kind != HeaderKind::Image) continue;
    groups[h.series_uid].push_back(std::move(h));
    if (!interrupter.progress(0.1 * double(n + 1) / double(files.size()))) return makeError(path, "cancelled");
  }
  if (groups.empty())
    return makeError(path, files.empty() ? "the folder holds no files" : "no DICOM image among its " +
                                                                             std::to_string(files.size()) + " files");
  std::vector<SliceHeader>* chosen = nullptr;
  if (!options.series_uid.empty()) {
    auto it = groups.find(options.series_uid);
    if (it == groups.end())
      return makeError(path, "no series " + options.series_uid + " here; the folder holds " + seriesList(groups));
    chosen = &it->second;
  } else if (groups.size() > 1) {
    return makeError(path, "mixed series: " + std::to_string(groups.size()) + " series in one folder (" +
                               seriesList(groups) + "); pick one with --series UID");
  } else {
    chosen = &groups.begin()->second;
  }
  std::vector<SliceHeader>& slices = *chosen;
  if (slices.size() == 1) {
    if (slices.front().frames > 1) return readOneFile(note, slices.front().path, options.max_bytes, info, options.approve);
    return makeError(path, "one slice is not a volume (" + fs::path(slices.front().path).filename().string() + ")");
  }
  if (Status s = checkSameGrid(path, slices); !s) return s.error();
  if (Status s = checkOneModality(path, slices); !s) return s.error();
  for (const SliceHeader& h : slices)
    if (Status s = checkPixelsInFile(h); !s) return s.error();
  for (const SliceHeader& h : slices)
    if (!h.has_position || !h.has_orientation)
      return makeError(h.path, "no Image Position or Orientation (Patient): the slices cannot be ordered");
  for (const SliceHeader& h : slices)
    if (std::fabs(h.gantry_tilt) > 1e-3)
      return makeError(h.path, "gantry tilt of " + mm(h.gantry_tilt) +
                                   " degrees: the slices are sheared; reconstruct the scan without tilt");

  // Order along the normal, then check that the steps are one spacing, straight along it.
  const SliceHeader& first = slices.front();
  const Vec n = cross({first.orientation[0], first.orientation[1], first.orientation[2]},
                      {first.orientation[3], first.orientation[4], first.orientation[5]});
  std::stable_sort(slices.begin(), slices.end(),
                   [&n](const SliceHeader& a, const SliceHeader& b) { return dot(a.position, n) < dot(b.position, n); });
  std::vector<double> steps;
  for (size_t k = 1; k < slices.size(); ++k) {
    const double step = dot(slices[k].position, n) - dot(slices[k - 1].position, n);
    if (step < 1e-4)
      return makeError(path, "two slices at one position: " + fs::path(slices[k - 1].path).filename().string() +
                                 " and " + fs::path(slices[k].path).filename().string());
    steps.push_back(step);
  }
  std::vector<double> sorted_steps = steps;
  std::nth_element(sorted_steps.begin(), sorted_steps.begin() + std::ptrdiff_t(sorted_steps.size() / 2),
                   sorted_steps.end());
  const double spacing = sorted_steps[sorted_steps.size() / 2];
  if (spacing > kMaxSpacingMm)
    return makeError(path, "its slices are " + mm(spacing) + " mm apart, beyond " + mm(kMaxSpacingMm) +
                               " mm: no scan of a tooth");
  for (size_t k = 0; k < steps.size(); ++k) {
    const std::string between =
        fs::path(slices[k].path).filename().string() + " and " + fs::path(slices[k + 1].path).filename().string();
    if (steps[k] > 1.5 * spacing) {
      const long missing = std::lround(steps[k] / spacing) - 1;
      return makeError(path, "missing slice: a gap of " + mm(steps[k]) + " mm between " + between + " where slices are " +
                                 mm(spacing) + " mm apart (about " + std::to_string(std::max(1L, missing)) +
                                 (missing == 1 ? " slice" : " slices") + " missing)");
    }
    if (std::fabs(steps[k] - spacing) > 0.1 * spacing)
      return makeError(path, "unevenly spaced slices: " + mm(steps[k]) + " mm between " + between + " where most are " +
                                 mm(spacing) + " mm apart");
  }
  const Vec span{slices.back().position[0] - first.position[0], slices.back().position[1] - first.position[1],
                 slices.back().position[2] - first.position[2]};
  const double along = dot(span, n);
  const Vec across{span[0] - along * n[0], span[1] - along * n[1], span[2] - along * n[2]};
  if (norm(across) > std::max(1e-3, 1e-3 * along)) {
    const double degrees = std::atan2(norm(across), along) * 180.0 / std::numbers::pi;
    return makeError(path, "gantry tilt: the slices shift " + mm(norm(across)) + " mm across their normal over the series (" +
                               mm(degrees) + " degrees); reconstruct the scan without tilt");
  }

  const uint64_t plane = uint64_t(first.rows) * uint64_t(first.columns);
  if (Status s = checkBudget(path, plane * slices.size(), options.max_bytes); !s) return s.error();
  if (options.approve)
    if (Status s = options.approve(plane * slices.size(), 0); !s) return s.error();
  GreyImage image;
  image.dims = {first.columns, first.rows, int32_t(slices.size())};
  const double pitch_k = along / double(slices.size() - 1);
  image.pitch_mm = {first.has_spacing ? first.spacing[1] : 1.0, first.has_spacing ? first.spacing[0] : 1.0, pitch_k};
  SliceHeader geometry = first;
  if (!geometry.has_spacing) geometry.spacing = {1.0, 1.0};
  image.scanner_from_voxel = scannerMatrix(geometry, first.position, {n[0] * pitch_k, n[1] * pitch_k, n[2] * pitch_k});
  copyDescription(first, image);
  image.values.resize(plane * slices.size());
  interrupter.start("reading DICOM slices");
  DicomSeriesInfo local;
  for (size_t k = 0; k < slices.size(); ++k) {
    if (Status s = decodePixels(note, slices[k].path, slices[k], image.values.data() + k * plane, &local); !s)
      return s.error();
    if (!interrupter.progress(0.1 + 0.9 * double(k + 1) / double(slices.size()))) return makeError(path, "cancelled");
  }
  interrupter.end();
  if (info) {
    *info = local;
    info->files_skipped = int32_t(files.size()) - int32_t(slices.size());  // not images, or another series
    info->series_uid = first.series_uid;
    info->files = int32_t(slices.size());
    info->slice_spacing_mm = pitch_k;
  }
  return image;
}

// The bytes a read of `path` takes in (the file, or the regular files below the folder), which
// the checking child's time limits scale with.
uint64_t inputBytes(const std::string& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return uint64_t(fs::file_size(path, ec));
  uint64_t total = 0;
  size_t files = 0;
  for (fs::recursive_directory_iterator it(path, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end && files <= kMaxSeriesFiles; it.increment(ec)) {
    std::error_code type_ec;
    if (!it->is_regular_file(type_ec)) continue;
    ++files;
    total += uint64_t(it->file_size(type_ec));
  }
  return total;
}

}  // namespace

Result<GreyImage> readDicomFile(const std::string& path, uint64_t max_bytes, DicomSeriesInfo* info) {
  quietGdcm();
  if (Status s = requireRegularFile(path); !s) return s.error();
  const auto check = [&](SandboxNote& note) -> Status {
    Result<GreyImage> r = readOneFile(note, path, max_bytes, nullptr);
    return r ? Status(Ok{}) : Status(r.error());
  };
  if (Status s = readInChild(path, max_bytes, inputBytes(path), check); !s) return s.error();
  SandboxNote here;  // the read in this process, once the child's succeeded: nothing to note
  return readOneFile(here, path, max_bytes, info);
}

Result<GreyImage> readDicomSeries(const std::string& path, const DicomReadOptions& options, Interrupter& interrupter,
                                  DicomSeriesInfo* info) {
  quietGdcm();
  SandboxNote here;
  if (options.in_process) return readSeries(here, path, options, interrupter, info);  // fuzzing and tests only
  const auto check = [&](SandboxNote& note) -> Status {
    Result<GreyImage> r = readSeries(note, path, options, nullInterrupter(), nullptr);
    return r ? Status(Ok{}) : Status(r.error());
  };
  if (Status s = readInChild(path, options.max_bytes, inputBytes(path), check); !s) return s.error();
  return readSeries(here, path, options, interrupter, info);
}

// ---- 6. writeDicomSeries -----------------------------------------------------------------------
namespace {

void put(gdcm::DataSet& ds, uint16_t group, uint16_t element, const char* vr, std::string value) {
  if (value.size() % 2 == 1) value += (std::string(vr) == "UI" ? '\0' : ' ');
  gdcm::DataElement de(gdcm::Tag(group, element));
  de.SetVR(gdcm::VR::GetVRType(vr));
  de.SetByteValue(value.data(), uint32_t(value.size()));
  ds.Replace(de);
}

void putUs(gdcm::DataSet& ds, uint16_t group, uint16_t element, uint16_t value) {
  const char bytes[2] = {char(value & 0xff), char(value >> 8)};  // little endian, as the transfer syntax
  gdcm::DataElement de(gdcm::Tag(group, element));
  de.SetVR(gdcm::VR::US);
  de.SetByteValue(bytes, 2);
  ds.Replace(de);
}

// A decimal string of at most 16 characters (the DS limit), as precise as that allows.
std::string decimal(double v) {
  char buf[40];
  for (int digits = 12; digits > 1; --digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strlen(buf) <= 16) break;
  }
  return buf;
}

std::string decimals(std::initializer_list<double> values) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : "\\") + decimal(v);
  return s;
}

}  // namespace

Result<std::vector<std::string>> writeDicomSeries(const std::string& dir, const GreyImage& image,
                                                  const DicomWriteOptions& options) {
  quietGdcm();
  std::error_code ec;
  if (fs::exists(dir, ec) && !(fs::is_directory(dir, ec) && fs::is_empty(dir, ec)))
    return makeError(dir, "not an empty folder; the series is written into a new or empty one");
  fs::create_directories(dir, ec);
  if (ec) return makeError(dir, "cannot create the folder: " + ec.message());
  const int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  if (nx < 1 || ny < 1 || nz < 1 || nx > 65535 || ny > 65535 || image.values.size() != size_t(image.voxelCount()))
    return makeError(dir, "the image's size does not suit DICOM slices");
  if (!(options.rescale_slope > 0) || !std::isfinite(options.rescale_intercept))
    return makeError(dir, "the rescale slope must be positive and the intercept finite");
  const std::array<double, 12>& m = image.scanner_from_voxel;
  const Vec ci{m[0], m[4], m[8]}, cj{m[1], m[5], m[9]}, ck{m[2], m[6], m[10]};
  if (!(norm(ci) > 0 && norm(cj) > 0)) return makeError(dir, "the image has no in-plane axes");
  const Vec r{ci[0] / norm(ci), ci[1] / norm(ci), ci[2] / norm(ci)};
  const Vec c{cj[0] / norm(cj), cj[1] / norm(cj), cj[2] / norm(cj)};

  gdcm::UIDGenerator uids;
  const std::string study = uids.Generate();
  const std::string series = options.series_uid.empty() ? std::string(uids.Generate()) : options.series_uid;
  const std::string frame_of_reference = uids.Generate();
  std::vector<int> order(static_cast<size_t>(nz));
  for (int k = 0; k < int(nz); ++k) order[size_t(k)] = k;
  if (options.scramble_names) std::shuffle(order.begin(), order.end(), std::mt19937(20261128u));
  const double lo = options.signed_pixels ? -32768.0 : 0.0, hi = options.signed_pixels ? 32767.0 : 65535.0;
  const char* ct_storage = gdcm::MediaStorage::GetMSString(gdcm::MediaStorage::CTImageStorage);

  std::vector<std::string> written;
  std::vector<char> pixels(size_t(nx * ny) * 2);
  for (int64_t k = 0; k < nz; ++k) {
    const float* src = image.values.data() + size_t(k * nx * ny);
    for (int64_t p = 0; p < nx * ny; ++p) {
      const double stored =
          std::clamp(std::nearbyint((double(src[p]) - options.rescale_intercept) / options.rescale_slope), lo, hi);
      const uint16_t bits = options.signed_pixels ? uint16_t(int16_t(stored)) : uint16_t(stored);
      pixels[size_t(p) * 2] = char(bits & 0xff);
      pixels[size_t(p) * 2 + 1] = char(bits >> 8);
    }
    gdcm::Writer writer;
    gdcm::DataSet& ds = writer.GetFile().GetDataSet();
    put(ds, 0x0008, 0x0016, "UI", ct_storage);
    put(ds, 0x0008, 0x0018, "UI", uids.Generate());
    put(ds, 0x0008, 0x0060, "CS", options.modality);
    put(ds, 0x0008, 0x0070, "LO", "dentsim");
    put(ds, 0x0008, 0x103e, "LO", options.series_description);
    put(ds, 0x0010, 0x0010, "PN", "Phantom^Tooth");
    put(ds, 0x0010, 0x0020, "LO", "DENTSIM-PHANTOM");
    put(ds, 0x0018, 0x0050, "DS", decimal(std::max(norm(ck), 1e-6)));
    put(ds, 0x0020, 0x000d, "UI", study);
    put(ds, 0x0020, 0x000e, "UI", series);
    put(ds, 0x0020, 0x0011, "IS", "1");
    put(ds, 0x0020, 0x0013, "IS", std::to_string(k + 1));
    put(ds, 0x0020, 0x0032, "DS",
        decimals({m[3] + double(k) * ck[0], m[7] + double(k) * ck[1], m[11] + double(k) * ck[2]}));
    put(ds, 0x0020, 0x0037, "DS", decimals({r[0], r[1], r[2], c[0], c[1], c[2]}));
    put(ds, 0x0020, 0x0052, "UI", frame_of_reference);
    putUs(ds, 0x0028, 0x0002, 1);
    put(ds, 0x0028, 0x0004, "CS", "MONOCHROME2");
    putUs(ds, 0x0028, 0x0010, uint16_t(ny));
    putUs(ds, 0x0028, 0x0011, uint16_t(nx));
    put(ds, 0x0028, 0x0030, "DS", decimals({norm(cj), norm(ci)}));  // between rows, then between columns
    putUs(ds, 0x0028, 0x0100, 16);
    putUs(ds, 0x0028, 0x0101, 16);
    putUs(ds, 0x0028, 0x0102, 15);
    putUs(ds, 0x0028, 0x0103, options.signed_pixels ? 1 : 0);
    put(ds, 0x0028, 0x1052, "DS", decimal(options.rescale_intercept));
    put(ds, 0x0028, 0x1053, "DS", decimal(options.rescale_slope));
    put(ds, 0x0028, 0x1054, "LO", options.hounsfield ? "HU" : "US");
    gdcm::DataElement pixel_data(kPixelData);
    pixel_data.SetVR(gdcm::VR::OW);
    pixel_data.SetByteValue(pixels.data(), uint32_t(pixels.size()));
    ds.Replace(pixel_data);
    writer.GetFile().GetHeader().SetDataSetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);

    char name[32];
    std::snprintf(name, sizeof name, "slice-%04d.dcm", order[size_t(k)] + 1);
    const std::string file = (fs::path(dir) / name).string();
    writer.SetFileName(file.c_str());
    if (!writer.Write()) return makeError(file, "cannot write the DICOM file");
    written.push_back(file);
  }
  return written;
}

}  // namespace dentsim
