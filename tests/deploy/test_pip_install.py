"""The README's install line of the Python client works on Debian 12 as written (PEP 668, no package index):

the line is read from README.md (so the README and this test cannot drift apart), pointed at a scratch venv and a
copy of clients/python (the build writes into the source folder), run with bash, and then the installed
`wish-client` runs from the venv and imports the installed package, not the source tree.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import unittest
from pathlib import Path

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
VENV_IN_README = "~/.local/wish-client"


def readme_install_line() -> str:
    for line in (SOURCE / "README.md").read_text(encoding="utf-8").splitlines():
        if "--no-build-isolation" in line and "clients/python" in line:
            return line.strip()
    raise AssertionError("README.md has no `pip install --no-build-isolation ... clients/python` line")


def _skip() -> str | None:
    r = subprocess.run(["/usr/bin/python3", "-c", "import ensurepip, setuptools"], capture_output=True)
    return None if r.returncode == 0 else "needs Debian's python3-venv and python3-setuptools (install-deps --test)"


@unittest.skipIf(_skip(), _skip() or "")
class ReadmeInstallLineTest(unittest.TestCase):
    def test_readme_line_installs_a_working_wish_client(self) -> None:
        tmp = Path(tempfile.mkdtemp(prefix="wish-pip-"))
        self.addCleanup(shutil.rmtree, tmp, True)
        shutil.copytree(SOURCE / "clients" / "python", tmp / "clients" / "python",
                        ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
        venv = tmp / "venv"
        line = readme_install_line()
        self.assertIn(VENV_IN_README, line)
        command = line.replace(VENV_IN_README, str(venv))
        # Debian's own python3 first on PATH (as on a fresh Debian 12), no pip configuration from the caller.
        env = {"PATH": "/usr/bin:/bin", "HOME": str(tmp), "PIP_NO_INDEX": "1", "PIP_DISABLE_PIP_VERSION_CHECK": "1"}
        r = subprocess.run(["bash", "-c", command], cwd=tmp, env=env, capture_output=True, text=True, timeout=600)
        self.assertEqual(r.returncode, 0, r.stdout[-2000:] + r.stderr[-2000:])

        exe = venv / "bin" / "wish-client"
        self.assertTrue(exe.exists())
        r = subprocess.run([str(exe), "--version"], env=env, capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout.strip(), r"^wish-client \d+\.\d+\.\d+$")
        r = subprocess.run([str(venv / "bin" / "python"), "-c", "import wish_client; print(wish_client.__file__)"],
                           cwd="/", env=env, capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(Path(r.stdout.strip()).is_relative_to(venv), r.stdout)


if __name__ == "__main__":
    unittest.main()
