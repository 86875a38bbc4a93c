"""bench/server_build_ab.py, the paired run-time check of two builds of the service: given the same executable twice
it finds the two servers' classifications identical (timings and request ids aside) and exits 0, and its comparison
ignores exactly the fields that differ between any two requests."""
import importlib.util
import os
import subprocess
import sys
import unittest

from loopback import free_ports
from wish_server_harness import SOURCE_DIR, WISH_BIN

SCRIPT = os.path.join(SOURCE_DIR, "bench", "server_build_ab.py")
SERVER = os.path.join(os.path.dirname(WISH_BIN), "wish-server")
MESH = os.path.join(SOURCE_DIR, "data", "meshes", "celegans_cell.obj")


def load_script():
    spec = importlib.util.spec_from_file_location("server_build_ab", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@unittest.skipUnless(os.path.exists(SERVER), "wish-server not found beside %s" % WISH_BIN)
class ServerBuildAB(unittest.TestCase):
    def test_the_same_build_twice_gives_identical_answers(self):
        ports = [str(p) for p in free_ports(2)]
        out = subprocess.run([sys.executable, SCRIPT, SERVER, SERVER, MESH, "--rounds", "1", "--ports", *ports],
                             capture_output=True, text=True, timeout=300)
        self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
        self.assertIn("responses without timings identical: yes", out.stdout)
        rows = [line.split() for line in out.stdout.splitlines() if line.split()[:1] in (["A"], ["B"])]
        self.assertEqual(len(rows), 2)
        for row in rows:
            self.assertGreater(float(row[1]), 0)  # CPU s per request

    def test_the_comparison_drops_timings_and_ids_only(self):
        strip = load_script().without_timings
        a = {"request_id": "x", "map": {"seconds": 1.0, "energy": 2.0}, "timings": {"fit": 3}, "xi": [1, 2]}
        b = {"request_id": "y", "map": {"seconds": 9.0, "energy": 2.0}, "timings": {"fit": 4}, "xi": [1, 2]}
        self.assertEqual(strip(a), strip(b))
        b["xi"] = [1, 3]
        self.assertNotEqual(strip(a), strip(b))
        b["xi"], b["map"]["energy"] = [1, 2], 2.5
        self.assertNotEqual(strip(a), strip(b))


if __name__ == "__main__":
    unittest.main()
