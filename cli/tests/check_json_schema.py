#!/usr/bin/python3
"""Checks one of owval's JSON documents against its JSON Schema (docs/schemas/, draft 2020-12).
Usage: check_json_schema.py SCHEMA FILE. Exit 0 valid, 1 not (each violation printed), 2 when
either file cannot be read as JSON. A schema may refer to another in its folder by file name
("parity.schema.json#/$defs/gate"): every *.schema.json beside SCHEMA is loaded for that.
Written for Debian's python3-jsonschema (4.10, RefResolver); newer versions still accept it."""
import json
import pathlib
import sys
import warnings

import jsonschema


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        print(f"{path}: {e}")
        sys.exit(2)


def line(error):
    """One violation in one line, cut short. A oneOf/anyOf's own message quotes the whole
    instance: the alternatives' deepest error (the one that matched furthest) says it better."""
    while error.context:
        error = max(error.context, key=lambda e: len(e.absolute_path))
    message = " ".join(error.message.split())
    if len(message) > 300:
        message = message[:300] + " ..."
    return f"{error.json_path}: {message}"


def main():
    if len(sys.argv) != 3:
        print("usage: check_json_schema.py SCHEMA FILE")
        return 2
    schema_path = pathlib.Path(sys.argv[1])
    schema = load(schema_path)
    doc = load(sys.argv[2])
    store = {p.name: load(p) for p in schema_path.parent.glob("*.schema.json")}
    jsonschema.Draft202012Validator.check_schema(schema)
    with warnings.catch_warnings():  # RefResolver is deprecated after 4.18, still supported
        warnings.simplefilter("ignore", DeprecationWarning)
        resolver = jsonschema.RefResolver(schema_path.name, schema, store=store)
        validator = jsonschema.Draft202012Validator(schema, resolver=resolver)
        problems = [line(e) for e in validator.iter_errors(doc)]
    for p in problems:
        print(p)
    if not problems:
        print(f"valid: {schema_path.name}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
