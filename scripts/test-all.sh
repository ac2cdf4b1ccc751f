#!/usr/bin/env bash
# Builds and runs every test: the normal build, then the same suites under ASan and UBSan. CI runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh

jobs=$(nproc)
# Vulkan tests run with the Khronos validation layers on (the gpu suite sets DENTSIM_VALIDATION=1);
# any validation error fails the test.
echo "== build (RelWithDebInfo)"
cmake --preset dev >/dev/null
cmake --build --preset dev -j "$jobs"
echo "== Vulkan device seen by the tests"
./build/src/app/dentsim gpu --validation
echo "== tests (RelWithDebInfo)"
ctest --preset dev -j "$jobs"

echo "== build (AddressSanitizer + UndefinedBehaviorSanitizer)"
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
echo "== tests (ASan + UBSan)"
ctest --preset asan -j "$jobs"
