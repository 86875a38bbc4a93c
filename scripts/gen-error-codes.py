#!/usr/bin/env python3
"""Writes the enum (and the description) of Error.code in proto/openapi.json from core/common/error_codes.cpp, the one
list of error codes. Only that one value in the file changes; the rest of the file keeps its layout.

    scripts/gen-error-codes.py          # rewrite proto/openapi.json
    scripts/gen-error-codes.py --check  # exit 1 when the file is not up to date (tests/common checks this too)
"""
import argparse
import json
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
LIST = ROOT / "core" / "common" / "error_codes.cpp"
OPENAPI = ROOT / "proto" / "openapi.json"
# HTTP status of each core category: read from the one table, kCategoryStatus in server/error_mapping.cpp.
STATUS_TABLE = ROOT / "server" / "error_mapping.cpp"
STATUS_ENTRY = re.compile(r"\{ErrorCategory::(\w+),\s*(\d+)\}")
ENTRY = re.compile(r'ErrorCodeInfo\{"([a-z0-9_]+)",\s*(?:C::(\w+)|kTransport),\s*(\d+),\s*"((?:[^"\\]|\\.)*)"\}')


def read_statuses():
    text = STATUS_TABLE.read_text()
    table = text[text.index("kCategoryStatus{"):]
    table = table[:table.index("}};")]
    statuses = {category: int(status) for category, status in STATUS_ENTRY.findall(table)}
    if not statuses:
        sys.exit(f"no category statuses found in {STATUS_TABLE}")
    return statuses


def read_list():
    STATUS = read_statuses()
    entries = []
    for code, category, transport, meaning in ENTRY.findall(LIST.read_text()):
        status = STATUS[category] if category else int(transport)
        entries.append((code, status, meaning))
    if not entries:
        sys.exit(f"no entries found in {LIST}")
    return entries


def code_schema(entries):
    by_status = {}
    for code, status, _ in entries:
        by_status.setdefault(status, []).append(code)
    summary = "; ".join(f"{s}: {', '.join(sorted(c))}" for s, c in sorted(by_status.items()))
    return {"type": "string", "enum": [c for c, _, _ in entries],
            "description": "Machine-readable reason, generated from core/common/error_codes.cpp (meanings there) by "
                           "scripts/gen-error-codes.py. By HTTP status: " + summary + "."}


def replace_code_value(text, value):
    """Replaces the JSON value of the "code" member of the Error schema's error object, found by brace matching."""
    anchor = text.index('"Error": {\n        "type": "object"')
    start = text.index('"code": {', anchor) + len('"code": ')
    depth, i, in_string = 0, start, False
    while True:
        ch = text[i]
        if in_string:
            if ch == "\\":
                i += 1
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                break
        i += 1
    return text[:start] + json.dumps(value) + text[i + 1:]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    old = OPENAPI.read_text()
    new = replace_code_value(old, code_schema(read_list()))
    json.loads(new)  # still valid JSON
    if args.check:
        if new != old:
            sys.exit("proto/openapi.json: Error.code is not up to date; run scripts/gen-error-codes.py")
        return
    OPENAPI.write_text(new)


if __name__ == "__main__":
    main()
