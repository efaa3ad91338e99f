#!/usr/bin/env bash
# The README's main job on the built-in one_sprig scenario.
set -euo pipefail
cd "$(dirname "$0")/.."
./build/owval inspect reference_trajectories/one_sprig/position_buffer.txt --particle 0 --axis y
