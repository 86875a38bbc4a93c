"""The glue's optimisation level stays in the glue: no numerical template in a linked executable comes from an -O1
object.

Why: the service's glue (targets marked GLUE in cmake/WishBuildSpeed.cmake: the CLI, the server, the wire format, the
pipeline's orchestration) compiles at -O1 in Release builds, the numerical areas at -O3. A template function that a
glue file and a numerical library both instantiate (an Eigen kernel, say) is emitted in both objects as a COMDAT
group, and the linker keeps the FIRST copy it meets and discards the rest. The glue's objects come first on every
executable's link line, so such a function would run at -O1 inside the numerical code — silently slower, and not
bit-identical to the tests' -O3 builds (session 19 saw the same effect with -O0 test programs: ξ differed in the 7th
digit). GCC records each function's optimisation level where it is parsed, hence the glue's own precompiled header.

What is checked, from the GNU ld link maps (-Map) that Release builds write for the glue executables
(<build>/link-maps/<target>.map): every code section (.text.<symbol>) kept from a glue object while an object of a
numerical library carried the same section (listed under "Discarded input sections"). Such sections of Eigen are
failures; the others (JSON, strings, enum parsing, destructors: code the glue itself runs) are printed as counts.

usage: check_glue_link_map.py --glue wish_pipeline,wish_wire,... MAP [MAP ...]
"""
import argparse
import collections
import re
import sys

# A section name, then (on the same line, or the next when the name is long) address, size and the input object.
SECTION = re.compile(r"^ (\.text\.\S+)\s+0x[0-9a-f]+\s+0x[0-9a-f]+\s+(\S+)$", re.M)
# The numerical template code that must keep the numerical libraries' -O3 copies.
NUMERICAL_TEMPLATES = re.compile(r"5Eigen")


def object_target(path):
    """The CMake target an input of the link belongs to: 'wish_pipeline' for '.../libwish_pipeline.a(x.o)',
    'wish' for 'cli/CMakeFiles/wish.dir/...o', None for anything else (system libraries, startup files)."""
    m = re.search(r"lib([\w.+-]+)\.a\(", path)
    if m:
        return m.group(1)
    m = re.search(r"CMakeFiles/([^/]+)\.dir/", path)
    return m.group(1) if m else None


def sections(text):
    """{section name: [input object, ...]} of one part of a map file."""
    out = collections.defaultdict(list)
    for m in SECTION.finditer(text):
        out[m.group(1)].append(m.group(2))
    return out


def glue_copies(map_text, glue):
    """[(section, kept from, discarded numerical objects)] for every code section kept from a glue object while a
    non-glue object of the build carried it too."""
    split = map_text.find("Linker script and memory map")
    if split < 0 or "Discarded input sections" not in map_text:
        raise ValueError("not a GNU ld link map (no 'Discarded input sections' / 'Linker script and memory map')")
    discarded, kept = sections(map_text[:split]), sections(map_text[split:])
    # A map this parser cannot read must not pass as "nothing found": every C++ executable here keeps code sections
    # and discards duplicate template copies.
    if not kept or not discarded:
        raise ValueError("no code sections parsed (kept %d, discarded %d): has the map's format changed?"
                         % (len(kept), len(discarded)))
    found = []
    for name, objects in kept.items():
        kept_from = objects[0]
        if object_target(kept_from) not in glue:
            continue
        numerical = [o for o in discarded.get(name, []) if object_target(o) not in (None, *glue)]
        if numerical:
            found.append((name, kept_from, numerical))
    return found


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--glue", required=True, help="comma-separated CMake targets compiled as glue")
    parser.add_argument("maps", nargs="+")
    args = parser.parse_args(argv)
    glue = {t for t in args.glue.split(",") if t}
    failures = 0
    for path in args.maps:
        with open(path, encoding="utf-8", errors="replace") as f:
            found = glue_copies(f.read(), glue)
        bad = [row for row in found if NUMERICAL_TEMPLATES.search(row[0])]
        print("%s: %d code sections kept from glue objects that numerical objects also had, %d of them Eigen's"
              % (path, len(found), len(bad)))
        by_target = collections.Counter(object_target(kept_from) for _, kept_from, _ in found)
        print("  kept from: " + ", ".join("%s %d" % kv for kv in by_target.most_common()))
        for name, kept_from, numerical in bad:
            print("  FAIL %s kept from %s (-O1), discarded from %s" % (name, kept_from, ", ".join(numerical[:3])))
        failures += len(bad)
    if failures:
        print("%d numerical template functions would run at the glue's optimisation level: instantiate them in a "
              "numerical library behind a non-template function, or keep the glue from using them" % failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
