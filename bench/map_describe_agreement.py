#!/usr/bin/env python3
"""Do `wish map FILE` and `wish describe FILE` end on the same chain attempt? (issue 37: one chain by default)

    python3 bench/map_describe_agreement.py build/release/cli/wish FILE_LIST

FILE_LIST: one mesh path per line. Prints one row per mesh: same|DIFF, the method of `wish map --json`, the map
method of `wish describe --json` (or the error code each refused with), and when the default canonical map ran, its
energy in each (the same relaxation from the same start gives the same energy), the file; then the count of each.
"""
import json
import subprocess
import sys
import tempfile
import os


def run(wish, args):
    p = subprocess.run([wish] + args, capture_output=True, text=True, timeout=600)
    try:
        return json.loads(p.stdout), p.stderr
    except ValueError:
        return None, p.stderr


def error_code(stderr):
    # "wish: error [code]: message" (cli/main.cpp)
    line = (stderr.strip().splitlines() or ["?"])[-1]
    return line[line.find("[") + 1:line.find("]")] if "[" in line else line[:60]


def main():
    wish, listing = sys.argv[1], sys.argv[2]
    files = [line.strip() for line in open(listing) if line.strip()]
    counts = {"same": 0, "DIFF": 0}
    with tempfile.TemporaryDirectory() as tmp:
        sphere = os.path.join(tmp, "sphere.ply")
        for f in files:
            m, m_err = run(wish, ["map", f, "--out", sphere, "--json"])
            d, d_err = run(wish, ["describe", f, "--json", "--quiet"])
            map_method = m["method"] if m else "error:" + error_code(m_err)
            map_energy = (m or {}).get("canonical", {}).get("energy")
            row = d[0] if isinstance(d, list) and d else {}
            describe_energy = None
            if "map" in row:
                describe_method = row["map"]["method"]
                describe_energy = row["map"].get("canonical", {}).get("energy")
            elif "error" in row:
                describe_method = "error:" + row["error"]["code"]
            else:
                describe_method = "error:" + error_code(d_err)
            same_energy = (map_energy == describe_energy or (map_energy is not None and describe_energy is not None
                           and abs(map_energy - describe_energy) <= 1e-9 * abs(describe_energy)))
            verdict = "same" if map_method == describe_method and same_energy else "DIFF"
            counts[verdict] += 1
            print(f"{verdict}\t{map_method}\t{describe_method}\t{map_energy}\t{describe_energy}\t{f}", flush=True)
    print(f"same {counts['same']}, different {counts['DIFF']} of {len(files)}")
    return 0 if counts["DIFF"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
