"""Running the `wish` executable from the CLI tests: one place for where it is and how a run that fails is reported.

WISH_BIN names the executable (ctest sets it); without it, build/release/cli/wish of this checkout. BLAS and OpenMP
run single-threaded, as ctest runs tests in parallel.
"""
import os
import subprocess

SOURCE_DIR = os.environ.get("WISH_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
WISH_BIN = os.environ.get("WISH_BIN", os.path.join(SOURCE_DIR, "build", "release", "cli", "wish"))
ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")


def run(*args, check=True):
    """Runs `wish ARGS`; with `check`, a non-zero exit raises AssertionError with the end of stdout and stderr."""
    p = subprocess.run([WISH_BIN, *args], capture_output=True, text=True, env=ENV, timeout=600)
    if check and p.returncode != 0:
        raise AssertionError("wish %s exited %d:\n%s\n%s" % (" ".join(args), p.returncode, p.stdout[-2000:],
                                                             p.stderr[-3000:]))
    return p


def read_text(path):
    with open(path) as f:
        return f.read()
