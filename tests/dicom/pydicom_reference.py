#!/usr/bin/python3
"""Reads DICOM files with pydicom, a reader independent of dentsim's GDCM, and prints what the tests compare.

Usage: pydicom_reference.py FILE...   (one JSON line per file)
       pydicom_reference.py --samples (the folder of pydicom's own sample files)
Each line: path, rows, columns, frames, the rescaled values' count, sum, min and max, the first
values, Image Position and Orientation (Patient) and Pixel Spacing when present. A file pydicom
cannot decode gives {"path": ..., "error": ...}.
"""
import json
import sys


def describe(path):
    import pydicom
    try:
        ds = pydicom.dcmread(path)
        values = ds.pixel_array.astype("float64")
        slope = float(getattr(ds, "RescaleSlope", 1) or 1)
        intercept = float(getattr(ds, "RescaleIntercept", 0) or 0)
        values = values * slope + intercept
        out = {
            "path": path,
            "rows": int(ds.Rows),
            "columns": int(ds.Columns),
            "frames": int(getattr(ds, "NumberOfFrames", 1) or 1),
            "count": int(values.size),
            "sum": float(values.sum()),
            "min": float(values.min()),
            "max": float(values.max()),
            "first": [float(v) for v in values.ravel()[:8]],
        }
        for key in ("ImagePositionPatient", "ImageOrientationPatient", "PixelSpacing"):
            if key in ds:
                out[key] = [float(v) for v in ds.data_element(key).value]
        out["SeriesInstanceUID"] = str(getattr(ds, "SeriesInstanceUID", ""))
        out["Modality"] = str(getattr(ds, "Modality", ""))
        return out
    except Exception as e:  # noqa: BLE001 - every failure is reported, not raised
        return {"path": path, "error": str(e).splitlines()[0] if str(e) else type(e).__name__}


def main(argv):
    if argv[1:] == ["--samples"]:
        from pydicom.data import get_testdata_file
        import os
        print(os.path.dirname(get_testdata_file("CT_small.dcm")))
        return 0
    for path in argv[1:]:
        print(json.dumps(describe(path)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
