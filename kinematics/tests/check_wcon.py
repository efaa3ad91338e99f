#!/usr/bin/python3
"""Checks a WCON file against wcon_schema.json and the spec's rules JSON Schema cannot express
(openworm/tracker-commons WCON_format.md). Usage: check_wcon.py SCHEMA FILE. Exit 0 valid, 1 not,
printing each violation."""
import json
import sys

import jsonschema

TOP_LEVEL = {"units", "data", "metadata", "files"}


def rules(doc):
    """The spec's rules beyond the schema: yields one message per violation."""
    units = doc["units"]
    for key in doc:
        if key not in TOP_LEVEL and not key.startswith("@"):
            yield f"top-level key {key!r}: unknown keys must start with '@'"
    records = doc["data"] if isinstance(doc["data"], list) else [doc["data"]]
    last_t = {}
    for i, r in enumerate(records):
        n = len(r["t"])
        for k in ("x", "y"):
            if len(r[k]) != n:
                yield f"data[{i}].{k}: {len(r[k])} entries for {n} time points"
        for j in range(min(n, len(r["x"]), len(r["y"]))):
            xs, ys = r["x"][j], r["y"][j]
            lx = len(xs) if isinstance(xs, list) else 1
            ly = len(ys) if isinstance(ys, list) else 1
            if lx != ly:
                yield f"data[{i}] time point {j}: x has {lx} values, y {ly}"
        for a, b in (("cx", "cy"), ("ox", "oy")):
            if (a in r) != (b in r):
                yield f"data[{i}]: {a} and {b} must come in pairs"
        for k in ("cx", "cy", "ox", "oy"):
            if k in r:
                if len(r[k]) != n:
                    yield f"data[{i}].{k}: {len(r[k])} entries for {n} time points"
                if k not in units:
                    yield f"units: {k} is used but has no unit"
        ts = [t for t in r["t"] if t is not None]
        previous = last_t.get(r["id"])
        for t in ts:
            if previous is not None and not t > previous:
                yield f"data[{i}].t: {t} after {previous}: times must increase"
            previous = t
        last_t[r["id"]] = previous


def main():
    with open(sys.argv[1]) as f:
        schema = json.load(f)
    with open(sys.argv[2]) as f:
        doc = json.load(f)  # a WCON file must be valid JSON
    validator = jsonschema.Draft202012Validator(schema)
    problems = [f"schema: {e.json_path}: {e.message}" for e in validator.iter_errors(doc)]
    if not problems:
        problems = list(rules(doc))
    for p in problems:
        print(p)
    if not problems:
        print("valid WCON")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
