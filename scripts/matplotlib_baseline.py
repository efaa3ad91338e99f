#!/usr/bin/env python3
"""The render benchmark's comparison point: what contributors do today, a matplotlib 3-D scatter
of one trajectory frame, saved as a 640x720 PNG, timed per frame (docs/benchmarks.md, Render).
Needs Debian's python3-matplotlib and python3-numpy (not an owval dependency).

usage: matplotlib_baseline.py POSITION_BUFFER [FRAMES]
"""
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def first_frame(path):
    with open(path) as f:
        header = [next(f) for _ in range(11)]
        count = sum(int(float(h)) for h in header[6:9])
        rows = np.loadtxt(f, max_rows=count)
    return rows


def main():
    rows = first_frame(sys.argv[1])
    frames = int(sys.argv[2]) if len(sys.argv) > 2 else 10
    colours = np.where(rows[:, 3] < 2, "tab:blue", np.where(rows[:, 3] < 3, "tab:green", "0.6"))
    start = time.perf_counter()
    for k in range(frames):
        fig = plt.figure(figsize=(6.4, 7.2), dpi=100)
        ax = fig.add_subplot(projection="3d")
        ax.scatter(rows[:, 0], rows[:, 2], rows[:, 1], c=colours, s=4)
        fig.savefig(f"/tmp/matplotlib_baseline_{k}.png")
        plt.close(fig)
    elapsed = time.perf_counter() - start
    print(f'{{"particles": {len(rows)}, "frames": {frames}, "fps": {frames / elapsed:.2f}}}')


if __name__ == "__main__":
    main()
