// Length units of mesh files and the tooth-size plausibility warning.
#include "io/mesh_units.h"

#include <cmath>
#include <cstdio>

namespace dentsim {
namespace {

bool plausibleExtent(double extent_mm) {
  return extent_mm >= kPlausibleMinExtentMm && extent_mm <= kPlausibleMaxExtentMm;
}

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

bool parseLengthUnit(std::string_view text, LengthUnit* unit) {
  LengthUnit parsed;
  if (text == "mm") parsed = LengthUnit::Millimetre;
  else if (text == "cm") parsed = LengthUnit::Centimetre;
  else if (text == "m") parsed = LengthUnit::Metre;
  // The micro sign U+00B5 and the Greek mu U+03BC look alike, and keyboards give either.
  else if (text == "um" || text == "\xC2\xB5m" || text == "\xCE\xBCm") parsed = LengthUnit::Micrometre;
  else return false;
  *unit = parsed;
  return true;
}

double millimetresPer(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Millimetre: return 1.0;
    case LengthUnit::Centimetre: return 10.0;
    case LengthUnit::Metre: return 1000.0;
    case LengthUnit::Micrometre: return 0.001;
  }
  return 1.0;
}

std::string_view lengthUnitSymbol(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Millimetre: return "mm";
    case LengthUnit::Centimetre: return "cm";
    case LengthUnit::Metre: return "m";
    case LengthUnit::Micrometre: return "um";
  }
  return "mm";
}

std::string toothExtentWarning(const Bounds3& bounds_mm, std::string_view where) {
  const double extent = bounds_mm.maxExtent();
  if (plausibleExtent(extent)) return "";
  std::string msg = where.empty() ? std::string() : std::string(where) + ": ";
  if (!std::isfinite(extent)) return msg + "extent is not finite; check the file's coordinates";
  msg += "extent " + shortNumber(extent) + " mm does not look like a tooth or a dental tool (" +
         shortNumber(kPlausibleMinExtentMm) + " to " + shortNumber(kPlausibleMaxExtentMm) +
         " mm); check --units or --scale";
  // The usual mistake is a file written in another unit, so name the unit that would fit. The
  // extents that the four factors make plausible do not overlap, so at most one hint applies.
  struct Hint {
    double factor;      // what the extent would be multiplied by
    const char* as;     // how to read the file
    const char* flag;   // the option that does it
  };
  static constexpr Hint kHints[] = {
      {10.0, "as centimetres", "--units cm"},
      {1000.0, "as metres", "--units m"},
      {0.001, "as micrometres", "--units um"},
      {0.1, "in tenths of a millimetre", "--scale 0.1"},
  };
  for (const Hint& h : kHints) {
    const double scaled = extent * h.factor;
    if (plausibleExtent(scaled))
      return msg + " (" + h.as + " it would be " + shortNumber(scaled) + " mm: " + h.flag + ")";
  }
  return msg;
}

std::string labelPitchWarning(double extent_mm, double pitch_mm, std::string_view where) {
  if (plausibleExtent(extent_mm)) return "";
  std::string msg = where.empty() ? std::string() : std::string(where) + ": ";
  return msg + "the tissue spans " + shortNumber(extent_mm) + " mm at " + shortNumber(pitch_mm) +
         " mm voxels, which does not look like a tooth (" + shortNumber(kPlausibleMinExtentMm) + " to " +
         shortNumber(kPlausibleMaxExtentMm) + " mm); if the file's voxel size is wrong, give the true one with --voxel-size";
}

}  // namespace dentsim
