#!/usr/bin/env bash
# The README's main job: the full 8-phase pipeline on the built-in one_sprig scenario.
set -euo pipefail
cd "$(dirname "$0")/.."
./build/owval pipeline one_sprig -o reports/one_sprig
echo "open reports/one_sprig/index.html"
