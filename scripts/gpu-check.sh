#!/usr/bin/env bash
# The check to run wherever a real GPU is lent: the GPU tests with validation, then bench mesh, voxelize and frames at levels 9 and 10, gathered with the device's name into one JSON file.
#
#   scripts/gpu-check.sh [--out DIR] [--levels 9,10] [--device NAME] [--no-tests]
#
# It builds the dev preset first when build/src/app/dentsim is missing (the packages of
# scripts/install-deps.sh must be there). Sized to end within 8 minutes on a machine with a real
# GPU: the benchmarks run once each (no repeats), 60 frames a path. On lavapipe it takes far longer
# at these levels; `--levels 7,8` checks the script itself. The figures go into docs/PERFORMANCE.md
# with the device's name (see its "GPU check" section).
set -euo pipefail
cd "$(dirname "$0")/.."

out=gpu-check
levels=9,10
device=""
tests=1
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$2; shift 2 ;;
    --levels) levels=$2; shift 2 ;;
    --device) device=$2; shift 2 ;;
    --no-tests) tests=0; shift ;;
    *) echo "gpu-check.sh: unknown argument '$1' (--out DIR, --levels L,L, --device NAME, --no-tests)" >&2; exit 2 ;;
  esac
done
mkdir -p "$out"
started=$(date +%s)
dentsim=./build/src/app/dentsim
if [ ! -x "$dentsim" ]; then
  echo "== build (dev preset)"
  cmake --preset dev >/dev/null
  cmake --build --preset dev -j "$(nproc)"
fi
device_args=()
[ -n "$device" ] && device_args=(--device "$device")
export DENTSIM_VALIDATION=1

echo "== device"
"$dentsim" gpu --json "${device_args[@]}" >"$out/device.json"

test_rc=0
if [ "$tests" = 1 ]; then
  echo "== GPU tests with validation (gpu, render, ui)"
  [ -n "$device" ] && export DENTSIM_DEVICE="$device"
  ctest --preset dev -L 'gpu|render|ui' -j "$(nproc)" --output-junit "$PWD/$out/gpu-tests.xml" >"$out/gpu-tests.log" 2>&1 || test_rc=$?
  tail -n 3 "$out/gpu-tests.log"
fi
# The benchmarks measure speed; validation would measure the layers.
unset DENTSIM_VALIDATION

echo "== bench mesh (levels $levels)"
"$dentsim" bench mesh --levels "$levels" --normals 216 --repeat 1 --frames 60 --bur-level "${levels##*,}" \
  --no-normals --out "$out/mesh" "${device_args[@]}" >"$out/mesh.log" 2>&1
echo "== bench voxelize (levels $levels)"
"$dentsim" bench voxelize --levels "$levels" --repeat 1 --out "$out/voxelize" "${device_args[@]}" >"$out/voxelize.log" 2>&1
echo "== bench frames (levels $levels)"
"$dentsim" bench frames --levels "$levels" --frames 60 --out "$out/frames" "${device_args[@]}" >"$out/frames.log" 2>&1

python3 - "$out" "$test_rc" "$started" <<'EOF'
import json, os, sys, time, xml.etree.ElementTree as ET
out, test_rc, started = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
def load(path):
    with open(os.path.join(out, path)) as f:
        return json.load(f)
device = load("device.json")
chosen = device.get("chosen", {})
result = {"check": "dentsim gpu-check", "device_name": chosen.get("name", "unknown"),
          "device_type": chosen.get("type", "unknown"), "device": device}
junit = os.path.join(out, "gpu-tests.xml")
if os.path.exists(junit):
    suite = ET.parse(junit).getroot()
    result["tests"] = {k: int(suite.get(k, 0)) for k in ("tests", "failures", "errors", "skipped")}
    result["tests"]["exit_code"] = test_rc
    result["tests"]["failed"] = [c.get("name") for c in suite.iter("testcase")
                                 if c.find("failure") is not None or c.find("error") is not None]
for name in ("mesh", "voxelize", "frames"):
    result[name] = load(os.path.join(name, name + ".json"))
result["seconds"] = int(time.time()) - started
with open(os.path.join(out, "gpu-check.json"), "w") as f:
    json.dump(result, f, indent=2)
print("wrote %s/gpu-check.json (%d s)" % (out, result["seconds"]))
EOF
exit "$test_rc"
