#!/usr/bin/env python3
"""The layers point one way (issue 35): the Python extension, the xtask and the facade's
library depend on the library crates, never on the command line's crate or its parser.

For each package below, `cargo tree -p PACKAGE` (with the edges named) must not list any
of the forbidden crates; prints each package's verdict and exits 1 on a violation. Run
from anywhere: `python3 scripts/check_layers.py`.
"""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# (package, edges, why): the dependencies that must stay free of the CLI layer
PACKAGES = [
    ("vibrissa-py", "normal,build,dev", "the Python extension builds on the library"),
    ("xtask", "normal,build,dev", "cargo xtask builds on the library"),
    ("vibrissa", "normal,build", "the facade a Rust user adds (its tests may run the CLI)"),
]
FORBIDDEN = ("vibrissa-cli", "clap", "indicatif")


def crate_name(line: str) -> str:
    """The crate a line of a `cargo tree` listing names (its tree drawing stripped)."""
    return line.lstrip("│├└─ \u00a0").split(" ")[0]


def offenders(tree: str) -> list:
    """The lines of a `cargo tree` listing that name a forbidden crate (`clap_builder`,
    `clap_derive` included)."""
    out = []
    for line in tree.splitlines():
        name = crate_name(line)
        if name in FORBIDDEN or name.startswith("clap_"):
            out.append(line.lstrip("│├└─ \u00a0"))
    return out


def main() -> int:
    bad = 0
    for package, edges, why in PACKAGES:
        tree = subprocess.run(
            ["cargo", "tree", "-p", package, "-e", edges],
            cwd=ROOT, check=True, capture_output=True, text=True,
        ).stdout
        found = offenders(tree)
        deps = len({crate_name(line) for line in tree.splitlines() if line.strip()})
        if found:
            bad += 1
            print(f"{package}: depends on {', '.join(sorted(set(f.split()[0] for f in found)))} "
                  f"({why}):")
            for f in found[:10]:
                print(f"    {f}")
        else:
            print(f"{package}: {deps} crates, none of {', '.join(FORBIDDEN)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
