#!/usr/bin/env bash
# Quick start on a fresh Debian 12 machine: install what is missing, build, and run the main job.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake --preset dev >/dev/null
cmake --build --preset dev
# The main job until `dentsim demo` exists: check the Vulkan device and run a kernel on it.
./build/src/app/dentsim gpu
