#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpora (fuzz/corpus/NAME) from small real-shaped files.

Text and configuration seeds are small files in Sibernetic's formats (a few particles, a few
frames: libFuzzer mutates small inputs fastest); HDF5 seeds are the text seeds converted by
`owval convert` (pass the owval binary); zlib seeds are zlib streams of chunk-like data behind the
2-byte size prefix fuzz_zlib_chunk.cpp reads; manifest seeds are the built-in scenario manifests;
WCON seeds are small tracks in owval's layout and in another producer's (keys in another order,
several ids, origins, units to convert, metadata).
Run: python3 fuzz/make_corpus.py build/cli/owval
"""
import gzip
import os
import shutil
import struct
import subprocess
import sys
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "fuzz", "corpus")


def write(target, name, data):
    os.makedirs(os.path.join(CORPUS, target), exist_ok=True)
    path = os.path.join(CORPUS, target, name)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())
    return path


def header(elastic, liquid, boundary, dt="2e-05", log_step=1):
    return "0\n20\n0\n20\n0\n20\n%d\n%d\n%d\n%s\n%s\n" % (elastic, liquid, boundary, dt, log_step)


def rows(points):
    return "".join("%g\t%g\t%g\t%g\n" % p for p in points)


def text_seeds():
    moving = [(5, 5, 5, 2.1), (6, 5.5, 5, 1.1)]
    walls = [(1, 1, 1, 3), (19, 1, 1, 3.1)]
    opencl = header(1, 1, 2, log_step=20) + rows(moving + walls)
    for f in range(1, 5):
        opencl += rows([(x + 0.1 * f, y - 0.05 * f, z, t) for x, y, z, t in moving])
    native = header(1, 1, 2) + "".join(rows(moving + walls) for _ in range(3))
    crlf = (header(0, 1, 0) + rows([(1.5, 2.5, 3.5, 1.1)] * 3)).replace("\n", "\r\n")
    seeds = {"opencl.txt": opencl, "native.txt": native, "crlf.txt": crlf,
             "liquid_only.txt": header(0, 2, 0) + rows([(1, 2, 3, 1), (2, 3, 4, 1)] * 2)}
    paths = []
    for name, text in seeds.items():
        paths.append(write("text", name, text))
    write("text", "opencl.txt.gz", gzip.compress(opencl.encode(), mtime=0))
    return paths


def config_seeds():
    connection = "1\t1.5\t0\t0\n" + "-1\t0\t0\t0\n" * 31
    connection += "0\t1.5\t1\t0\n" + "-1\t0\t0\t0\n" * 31
    memindex = "0\n" + "-1\n" * 6 + "0\n" + "-1\n" * 6
    body = ("[simulation box]\n0\n20\n0\n20\n0\n20\n"
            "[position]\n5\t5\t5\t2.1\n6.5\t5\t5\t2.1\n7\t7\t7\t2.2\n8\t8\t8\t1.1\n1\t1\t1\t3\n"
            "[velocity]\n0\t0\t0\t0\n0\t0\t0\t0\n0\t0\t0\t0\n0\t0\t0\t0\n0.57735\t0.57735\t0.57735\t3\n"
            "[connection]\n" + connection + "-1\t0\t0\t0\n" * 32)
    membranes = "[membranes]\n0\t1\t2\n[particleMemIndex]\n" + memindex + "-1\n" * 7
    write("config", "three_elastic.cfg", body + membranes + "[end]\n")
    write("config", "params.cfg", "[physical parameters]\nh: 3.34\ntimeStep: 2.0e-05 // dt\n"
          + body + "[membranes]\n[particleMemIndex]\n[end]\n")
    write("config", "liquid.cfg", "[simulation box]\n0\n30\n0\n30\n0\n30\n[position]\n"
          "3\t3\t3\t1.1\n4\t4\t4\t1\n[velocity]\n0\t0\t0\t1\n0\t0\t0\t1\n[connection]\n"
          "[membranes]\n[particleMemIndex]\n[end]\n")


def hdf5_seeds(owval, text_paths):
    out = os.path.join(CORPUS, "hdf5")
    os.makedirs(out, exist_ok=True)
    for path in text_paths:
        name = os.path.splitext(os.path.basename(path))[0] + ".h5"
        subprocess.run([owval, "--quiet", "convert", path, os.path.join(out, name)], check=True)


def zlib_seeds():
    import random
    rng = random.Random(1)
    floats = struct.pack("<%df" % 48, *[10 + 0.01 * i + rng.uniform(-1e-3, 1e-3) for i in range(48)])
    planes = bytes(floats[4 * e + b] for b in range(4) for e in range(48))  # HDF5 shuffle
    samples = {"shuffled": planes, "text": b"worm muscle particle elastic\n" * 20,
               "zeros": bytes(4096), "random": bytes(rng.getrandbits(8) for _ in range(400))}
    for name, data in samples.items():
        for level in (0, 1, 9):
            size = struct.pack(">H", len(data) // 4)
            write("zlib_chunk", "%s_%d" % (name, level), size + zlib.compress(data[: len(data) // 4 * 4], level))


def manifest_seeds():
    src = os.path.join(ROOT, "scenarios", "manifests")
    os.makedirs(os.path.join(CORPUS, "manifest"), exist_ok=True)
    for name in sorted(os.listdir(src)):
        if name.endswith(".json"):
            shutil.copy(os.path.join(src, name), os.path.join(CORPUS, "manifest", name))


def wcon_seeds():
    units = '"units": {"t": "s", "x": "mm", "y": "mm", "cx": "mm", "cy": "mm"}'
    write("wcon", "owval_layout.wcon",
          '{\n ' + units + ',\n "metadata": {"software": {"name": "owval", "version": "0.1.0", '
          '"featureID": "@owval", "settings": {"backend": "pcisph"}}},\n "@owval": {"frames": 3},\n'
          ' "data": [\n  {"id": "1", "head": "L",\n   "t": [0,0.003,0.006],\n'
          '   "cx": [0.5,0.51,0.52],\n   "cy": [1,1,1],\n'
          '   "x": [\n    [0,0.1,0.2],\n    [0,0.1,0.21],\n    [0,0.1,0.22]],\n'
          '   "y": [\n    [1,1.1,1.2],\n    [1,1.1,1.2],\n    [1,1.1,1.2]]}\n ]\n}\n')
    write("wcon", "foreign_order.wcon",
          '{"data": [{"x": [[1000, 3000], [2000, 1000]], "cy": [1, 2], "cx": [5, 6], '
          '"y": [[1, 2], [2, 3]], "id": "7", "t": [0, 500], "ox": [100, 100], "@X": {"t": [9]}}, '
          '{"id": "8", "t": [0], "x": [[1]], "y": [[1]]}, '
          '{"id": "7", "t": [600], "x": [4000], "y": [5], "cx": [7], "cy": [8]}], '
          '"units": {"t": "ms", "x": "um", "y": "mm", "cx": "um", "cy": "mm"}}\n')
    write("wcon", "single_record.wcon",
          '{"units": {"t": "minutes", "x": "m", "y": "cm"}, "metadata": 5, '
          '"data": {"id": "w", "t": [0, 1e-3], "x": [[0, -1.5e-3], [2e-4, 1]], '
          '"y": [[0, 0], [1e2, -0]]}}\n')


def pack_zarr(store):
    """A store directory as fuzz_zarr.cpp's container: "@@ PATH\n" then the file's bytes."""
    sections = []
    for directory, _, files in sorted(os.walk(store)):
        for name in sorted(files):
            path = os.path.join(directory, name)
            with open(path, "rb") as f:
                sections.append(b"@@ " + os.path.relpath(path, store).encode() + b"\n" + f.read())
    return b"\n".join(sections)


def zarr_seeds(owval, text_paths):
    """Stores written by `owval convert` from the text seeds, and variants another writer of the
    contract may produce: uncompressed chunks in mm, a missing chunk (the fill value)."""
    import json
    import tempfile
    for path in text_paths:
        if path.endswith("crlf.txt"):
            continue
        with tempfile.TemporaryDirectory() as tmp:
            store = os.path.join(tmp, "s.zarr")
            subprocess.run([os.path.abspath(owval), "--quiet", "convert",
                            os.path.relpath(path, ROOT), store], check=True, cwd=ROOT)
            name = os.path.splitext(os.path.basename(path))[0]
            write("zarr", name + ".zarr", pack_zarr(store))
            if name != "opencl":
                continue
            for array in ("body/positions", "body/time", "body/types"):
                meta_path = os.path.join(store, array, ".zarray")
                with open(meta_path) as f:
                    meta = json.load(f)
                if meta.get("compressor"):
                    for chunk in os.listdir(os.path.join(store, array)):
                        if not chunk.startswith("."):
                            cp = os.path.join(store, array, chunk)
                            with open(cp, "rb") as f:
                                raw = zlib.decompress(f.read())
                            with open(cp, "wb") as f:
                                f.write(raw)
                meta["compressor"] = None
                with open(meta_path, "w") as f:
                    json.dump(meta, f)
            with open(os.path.join(store, "body/positions/.zattrs"), "w") as f:
                json.dump({"units": "mm"}, f)
            write("zarr", "opencl_raw_mm.zarr", pack_zarr(store))
            os.remove(os.path.join(store, "body/positions/0.0.0"))
            write("zarr", "opencl_fill_value.zarr", pack_zarr(store))


def backends_seeds():
    shutil.copy(os.path.join(ROOT, "docs", "owval-backends.example.json"),
                write("backends", "example.json", ""))
    write("backends", "command_and_store.json",
          '{"backends": {\n  "opencl": {\n    "command": "./Sibernetic -no_g -f {config} '
          'timelimit={time} logstep={log_step} lpath={out}",\n    "working_directory": '
          '"~/sibernetic",\n    "output": "{out}/position_buffer.txt",\n    "layout": "opencl",\n'
          '    "store": "/work/shared/reference"},\n  "opencl-recorded": {"store": "recorded"}}}\n')
    write("backends", "set_and_description.json",
          '{"backends": {"port": {"command": "port --k {set:k} -o {out}", "layout": "hdf5", '
          '"output": "{out}/trajectory.h5", "description": "a port", '
          '"set": {"k": "1.5", "n": 3, "flag": true}}}}\n')


# fuzz_history.cpp's reference.txt, whose FNV-1a 64 a gradient fit's loss record must carry.
HISTORY_REFERENCE = ("0\n20\n0\n20\n0\n20\n1\n1\n2\n2e-05\n20\n"
                     "5\t5\t5\t2.1\n6\t5.5\t5\t1.1\n1\t1\t1\t3\n19\t1\t1\t3.1\n"
                     "5.1\t4.95\t5\t2.1\n6.1\t5.45\t5\t1.1\n"
                     "5.2\t4.9\t5\t2.1\n6.2\t5.4\t5\t1.1\n")


def fnv1a64(data):
    h = 1469598103934665603
    for c in data:
        h = ((h ^ c) * 1099511628211) % (1 << 64)
    return "%016x" % h


def history_seeds():
    """Fit histories as `owval fit` writes them: the engine's, a named backend's, the XPBD
    model's (its loss reference held to the target's reference.txt, so the checklist reads on)."""
    import json
    engine = {
        "schema": "owval.fit.history/2", "converged": True, "evaluations": 6,
        "solver": "lm", "stop_reason": "loss below threshold", "wall_s": 1.5,
        "loss_threshold": 1e-4,
        "parameters": [{"name": "elasticity_coefficient", "start": 1.62e8, "log_space": True,
                        "lower": -1e300, "upper": 1e300}],
        "targets": [{"metric": "period", "value": 7.246e-4, "scale": 7.25e-4, "weight": 1,
                     "track": {"particle": 0, "axis": "y"}},
                    {"metric": "half_amplitude", "value": 0.1, "scale": 0.1, "weight": 0.25,
                     "track": {"particle": 0, "axis": "y"}}],
        "iterations": [
            {"iteration": 0, "loss": 0.13, "parameters": {"elasticity_coefficient": 1.62e8},
             "residuals": [0.36055512754639896, 0.0], "evaluations": 3},
            {"iteration": 1, "loss": 8.1e-07, "parameters": {"elasticity_coefficient": 2.99e8},
             "residuals": [0.0009, 0.0], "evaluations": 6}],
        "final": {"loss": 8.1e-07, "parameters": {"elasticity_coefficient": 2.99e8}},
        "simulation": {"kind": "engine", "backend": "pcisph",
                       "configuration": {"file": "configuration.txt",
                                         "fnv1a64": "0123456789abcdef", "source": "one_sprig"},
                       "duration_s": 0.0004, "log_step": 20, "integrator": "euler",
                       "muscles": "auto", "apply_physical_parameters": True, "constants": {}}}
    write("history", "engine.json", json.dumps(engine, indent=1) + "\n")
    backend = json.loads(json.dumps(engine))
    backend["simulation"] = {"kind": "backend", "name": "port", "command": "port -o {out}",
                             "configuration": engine["simulation"]["configuration"],
                             "duration_s": 0.0004, "time_step_s": 2e-05, "log_step": 20}
    write("history", "backend.json", json.dumps(backend, indent=1) + "\n")
    model = json.loads(json.dumps(engine))
    model["targets"] = []
    for it in model["iterations"]:
        del it["residuals"]
    model["iterations"][1]["residuals"] = [0.0009]
    model["iterations"][0]["residuals"] = [0.36055512754639896]
    model["simulation"] = {"kind": "xpbd_model", "steps": 20,
                           "configuration": engine["simulation"]["configuration"],
                           "loss": {"groups": [], "scale": 0.1, "track": {"particle": 0, "axis": "y"},
                                    "reference": {"file": "reference.txt",
                                                  "fnv1a64": fnv1a64(HISTORY_REFERENCE.encode())}}}
    write("history", "xpbd_model.json", json.dumps(model, indent=1) + "\n")


def side_files_seeds():
    """The first lines of Sibernetic's own worm_motion_log.txt and muscles_activity_buffer.txt
    (../shared/reference), plain and gzip-compressed, and a line with empty bins."""
    log = os.path.join(ROOT, "..", "shared", "reference", "worm_alone_0.6s", "worm_motion_log.txt.gz")
    with gzip.open(log, "rb") as f:
        lines = f.read().split(b"\n")
    write("side_files", "two_lines.txt", b"\n".join(lines[:2]) + b"\n")
    write("side_files", "three_lines.txt.gz", gzip.compress(b"\n".join(lines[:3]) + b"\n", mtime=0))
    empty = b"\t".join([b"1e-3", b"X:"] + [b"0"] * 97 + [b"1", b"2", b"Y:"] + [b"0"] * 97 +
                       [b"3", b"4", b"Z:"] + [b"0"] * 97 + [b"5", b"6"])
    write("side_files", "empty_bins.txt", b"\n" + empty + b"\r\n\n")
    muscles = os.path.join(ROOT, "..", "shared", "reference", "worm_alone_0.6s",
                           "muscles_activity_buffer.txt")
    with open(muscles, "rb") as f:
        rows = f.read().split(b"\n")
    write("side_files", "muscles_two_lines.txt", b"\n".join(rows[:2]) + b"\n")
    write("side_files", "muscles_three_lines.txt.gz",
          gzip.compress(b"\n".join(rows[99:102]) + b"\n", mtime=0))


def targets_seeds():
    """`owval fit --param` and `--target` values as docs and tests write them."""
    write("targets", "params.txt", "elasticity_coefficient=1.62e8:log\n"
          "viscosity=0.1:lin:0:1\nk=2:1:3\n")
    write("targets", "targets.txt", "period=0.7246e-3:scale=0.725e-3\n"
          "half_amplitude=0.1:scale=0.1:weight=0.25\nrms=0:ref=reference.h5:scale=1\n"
          "equilibrium=-3e-2:weight=0\n")


def main():
    wcon_seeds()
    text_paths = text_seeds()
    config_seeds()
    zlib_seeds()
    manifest_seeds()
    backends_seeds()
    history_seeds()
    side_files_seeds()
    targets_seeds()
    if len(sys.argv) > 1:
        hdf5_seeds(sys.argv[1], text_paths)
        zarr_seeds(sys.argv[1], text_paths)


if __name__ == "__main__":
    main()
