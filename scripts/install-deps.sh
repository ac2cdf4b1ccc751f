#!/usr/bin/env bash
# Installs every Debian 12 package dentsim needs to build, test and benchmark; idempotent, no prompts.
set -euo pipefail

# Build and test: compiler, CMake, shaders, Vulkan on lavapipe with validation, libraries, and the
# headless browser that renders the class report in its test.
packages=(
  build-essential cmake ninja-build pkg-config clang lld
  glslc glslang-tools spirv-tools
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  libglfw3-dev libglm-dev libimgui-dev libopenal-dev libusb-1.0-0-dev libhidapi-dev
  umockdev libumockdev-dev
  util-linux  # setpriv: the permission tests run dentsim as the user nobody
  stress-ng   # scripts/stress-tests.sh: the tests that depend on timing, under full CPU load
  xvfb xauth
  libgtest-dev libgmock-dev
  libnifti2-dev zlib1g-dev libzstd-dev libxxhash-dev
  libgdcm-dev libgdcm-tools libteem-dev  # a scanner's DICOM series (GDCM) and NRRD volumes (Teem)
  python3-pydicom python3-numpy          # an independent DICOM reader, and its sample files, for the tests
  libcli11-dev libstb-dev nlohmann-json3-dev libmeshoptimizer-dev
  chromium libcurl4-openssl-dev uuid-dev python3
  dpkg-dev  # dpkg-shlibdeps: cpack -G DEB finds the lab package's Depends (cmake/Packaging.cmake)
)
# The learning-record tests' validator runs on Node (tests/xapi); a Node already on the PATH is kept.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  packages+=(nodejs npm)
fi
# Benchmark peers, measured beside dentsim in the same run (docs/PERFORMANCE.md): OpenVDB and VTK.
if [[ "${DENTSIM_NO_PEERS:-0}" != 1 ]]; then
  packages+=(libopenvdb-dev libtbb-dev libboost-iostreams-dev libblosc-dev libvtk9-dev)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
else
  echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Test tools from npm, pinned by tests/xapi/package-lock.json: the independent xAPI validator.
(cd "$(dirname "$0")/../tests/xapi" && npm ci --no-audit --no-fund --silent)
# The real LRS the learning-record tests send to and read back from (tests/lrs, pinned by its
# package-lock.json): Learning Locker's statement service, a GPL-3 server the tests run beside
# dentsim, never linked into it. No package's install scripts run.
(cd "$(dirname "$0")/../tests/lrs" && npm ci --ignore-scripts --omit=dev --no-audit --no-fund --silent)
echo "install-deps: done"
