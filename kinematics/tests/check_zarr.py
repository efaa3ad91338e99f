#!/usr/bin/python3
"""Reads an owval OME-Zarr with zarr-python and compares every value with raw little-endian files
written by the C++ test. Usage: check_zarr.py STORE POSITIONS.f32 TYPES.f32 TIME.f64 FRAMES N."""
import sys

import numpy as np
import zarr


def main():
    store, positions, types, time, frames, n = sys.argv[1:7]
    frames, n = int(frames), int(n)
    root = zarr.open_group(store, mode="r")
    p, t, tm = root["body/positions"], root["body/types"], root["body/time"]
    problems = []
    if p.shape != (frames, n, 3) or p.dtype != np.float32:
        problems.append(f"body/positions: shape {p.shape} dtype {p.dtype}")
    if p.chunks[1:] != (n, 3):
        problems.append(f"body/positions: chunks {p.chunks} not by frames")
    expected = np.fromfile(positions, dtype="<f4").reshape(frames, n, 3)
    if not problems and not np.array_equal(p[:], expected):
        problems.append(f"body/positions: {np.count_nonzero(p[:] != expected)} values differ")
    if not np.array_equal(t[:], np.fromfile(types, dtype="<f4")):
        problems.append("body/types differ")
    if not np.array_equal(tm[:], np.fromfile(time, dtype="<f8")):
        problems.append("body/time differs")
    attrs = root.attrs.asdict().get("@owval", {})
    for key in ("provenance", "time_step_s", "log_step", "simulation_scale_m"):
        if key not in attrs:
            problems.append(f"root attribute @owval.{key} missing")
    if p.attrs.get("units") != "micrometre":
        problems.append("body/positions: units attribute is not micrometre")
    for x in problems:
        print(x)
    if not problems:
        print(f"zarr read back: {frames * n * 3} positions, {n} types, {frames} times equal")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
