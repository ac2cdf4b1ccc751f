#!/usr/bin/env bash
# Quick start on a fresh Debian 12 machine: install what is missing, build, and run the main job.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake --preset dev >/dev/null
cmake --build --preset dev
# Check the Vulkan device, then the main job: the scripted caries removal on the built-in molar,
# shown in the simulator window (headless where no display answers), recorded and scored
# (dentsim-demo/ holds the session, the volumes, the score, its picture and frames).
./build/src/app/dentsim gpu
./build/src/app/dentsim demo --out dentsim-demo
