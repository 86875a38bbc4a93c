#!/usr/bin/python3
"""Our own Dockerfile checks (no Docker engine, no hadolint on the project's machines).

    /usr/bin/python3 scripts/lint-dockerfile.py docker/Dockerfile [more Dockerfiles]

Rules (each failure names the line):
  DF001 every FROM is Debian 12 bookworm (an ARG default counts), never :latest or an unpinned tag
  DF002 the final stage runs as a non-root USER (not root / 0)
  DF003 a HEALTHCHECK is present and probes /healthz
  DF004 no `curl|sh`-style downloads piped into a shell
  DF005 every RUN with `apt-get install` also removes /var/lib/apt/lists in the same RUN
  DF006 the build installs packages with scripts/install-deps.sh (the one list CI uses)
  DF007 `apt-get install` uses --no-install-recommends
Exit status 1 when any rule fails.
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from pathlib import Path


@dataclass
class Instruction:
    line: int      # 1-based line of the instruction's first line
    keyword: str   # upper-case
    args: str      # continuation lines joined


def parse(text: str) -> list[Instruction]:
    """Instructions with backslash continuations joined; comments and blank lines dropped."""
    out: list[Instruction] = []
    buf, start = "", 0
    for no, raw in enumerate(text.splitlines(), 1):
        line = raw.rstrip()
        if not buf and (not line.strip() or line.lstrip().startswith("#")):
            continue
        if buf and line.lstrip().startswith("#"):
            continue  # comment inside a continuation
        if not buf:
            start = no
        if line.endswith("\\"):
            buf += line[:-1] + " "
            continue
        buf += line
        keyword, _, args = buf.strip().partition(" ")
        out.append(Instruction(start, keyword.upper(), args.strip()))
        buf = ""
    return out


def check(path: Path) -> list[str]:
    text = path.read_text(encoding="utf-8")
    ins = parse(text)
    errors: list[str] = []

    def err(rule: str, line: int, message: str) -> None:
        errors.append(f"{path}:{line}: {rule} {message}")

    args = {}
    for i in ins:
        if i.keyword == "ARG" and "=" in i.args:
            k, v = i.args.split("=", 1)
            args[k.strip()] = v.strip().strip('"')
    froms = [i for i in ins if i.keyword == "FROM"]
    if not froms:
        err("DF001", 1, "no FROM")
    stage_names = set()
    for f in froms:
        words = f.args.split()
        words = [w for w in words if not w.startswith("--")]
        image = re.sub(r"\$\{?(\w+)\}?", lambda m: args.get(m.group(1), m.group(0)), words[0])
        if len(words) >= 3 and words[1].upper() == "AS":
            stage_names.add(words[2])
        if image in stage_names:
            continue
        if not re.fullmatch(r"(docker\.io/(library/)?)?debian:bookworm(-slim)?(-\d{8})?(@sha256:[0-9a-f]{64})?", image):
            err("DF001", f.line, f"FROM {image!r} is not Debian 12 bookworm (debian:bookworm or bookworm-slim)")

    last_from = froms[-1].line if froms else 0
    users = [i for i in ins if i.keyword == "USER" and i.line > last_from]
    if not users:
        err("DF002", last_from, "the final stage sets no USER: the service would run as root")
    elif users[-1].args.split(":")[0] in ("root", "0"):
        err("DF002", users[-1].line, "the final USER is root")

    hc = [i for i in ins if i.keyword == "HEALTHCHECK"]
    if not hc:
        err("DF003", 1, "no HEALTHCHECK")
    elif not any("/healthz" in i.args for i in hc):
        err("DF003", hc[-1].line, "HEALTHCHECK does not probe /healthz")

    pipe_to_shell = re.compile(r"\b(curl|wget)\b[^|;&]*\|\s*(sudo\s+)?(ba|z|da)?sh\b")
    for i in ins:
        if i.keyword != "RUN":
            continue
        if pipe_to_shell.search(i.args):
            err("DF004", i.line, "downloads piped into a shell (curl|sh): install from Debian packages instead")
        if re.search(r"apt-get\s+(-\S+\s+)*install", i.args):
            if "/var/lib/apt/lists" not in i.args or "rm " not in i.args:
                err("DF005", i.line, "apt-get install without `rm -rf /var/lib/apt/lists/*` in the same RUN")
            if "--no-install-recommends" not in i.args:
                err("DF007", i.line, "apt-get install without --no-install-recommends")
        if "install-deps.sh" in i.args and "/var/lib/apt/lists" not in i.args:
            err("DF005", i.line, "scripts/install-deps.sh runs apt-get: clean /var/lib/apt/lists in the same RUN")
    if not any(i.keyword == "RUN" and "scripts/install-deps.sh" in i.args for i in ins):
        err("DF006", 1, "the build does not use scripts/install-deps.sh (the package list CI uses)")
    return errors


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__, file=sys.stderr)
        return 2
    errors = [e for p in argv for e in check(Path(p))]
    for e in errors:
        print(e, file=sys.stderr)
    if not errors:
        print(f"lint-dockerfile: {', '.join(argv)} ok")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
