#!/usr/bin/env python3
"""Checks of the README a user reads first (issue 35), run by `.ci/run`.

Usage: python3 scripts/check_readme.py [README.md]

Fails (exit 1, one line per finding) when
- the README is 25 kB (25,000 bytes) or more;
- a table cell has more than 300 characters (the README's tables carry one-line cells: the
  history behind a figure belongs in docs/performance.md);
- a link or image of the README or of a page under docs/ does not resolve: a relative path
  that is not a file or folder of the repository, a path that leaves the repository
  (`../`), or an anchor (`#section`, `file.md#section`) that names no heading;
- the README names a path outside the repository (`../shared/...`): the thesis is cited, not
  linked by path;
- the two commands at the very top are not the first code block.
"""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MAX_BYTES = 25_000
MAX_CELL = 300
TOP_COMMANDS = (
    "cargo run --release -p vibrissa-cli -- demo",
    "bash scripts/test.sh",
)

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(path):
    text = strip_code(path.read_text())
    return {slug(m.group(1)) for m in re.finditer(r"^#{1,6}\s+(.*)$", text, re.M)}


def strip_code(text):
    """`text` without fenced code blocks (a `# comment` in a shell block is no heading)."""
    return re.sub(r"^```.*?^```", "", text, flags=re.M | re.S)


def table_cells(text):
    """(line number, cell) of every cell of every table row outside code blocks."""
    in_code = False
    for n, line in enumerate(text.split("\n"), 1):
        if line.startswith("```"):
            in_code = not in_code
            continue
        if in_code or not line.lstrip().startswith("|"):
            continue
        # split at pipes that are not escaped (\|) and not inside backticks
        cells, cur, tick, prev = [], "", False, ""
        for c in line.strip().strip("|"):
            if c == "`":
                tick = not tick
            if c == "|" and not tick and prev != "\\":
                cells.append(cur)
                cur = ""
            else:
                cur += c
            prev = c
        cells.append(cur)
        for cell in cells:
            yield n, cell.strip()


def check_links(path, problems):
    text = strip_code(path.read_text())
    for m in LINK.finditer(text):
        target = m.group(1)
        line = text.count("\n", 0, m.start()) + 1
        where = f"{path.relative_to(ROOT)}:{line}"
        if re.match(r"^[a-z]+:", target):
            continue  # an absolute URL: not checked here (no network)
        file_part, _, anchor = target.partition("#")
        dest = (path.parent / file_part).resolve() if file_part else path
        try:
            dest.relative_to(ROOT)
        except ValueError:
            problems.append(f"{where}: link {target} leaves the repository")
            continue
        if not dest.exists():
            problems.append(f"{where}: link {target} does not resolve ({dest.relative_to(ROOT)} missing)")
            continue
        if anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            problems.append(f"{where}: link {target}: no heading #{anchor} in {dest.relative_to(ROOT)}")


def main(argv):
    readme = Path(argv[0]).resolve() if argv else ROOT / "README.md"
    problems = []
    raw = readme.read_bytes()
    name = readme.relative_to(ROOT)
    if len(raw) >= MAX_BYTES:
        problems.append(f"{name}: {len(raw)} bytes, the limit is under {MAX_BYTES}")
    text = raw.decode("utf-8")
    for n, cell in table_cells(text):
        if len(cell) > MAX_CELL:
            problems.append(f"{name}:{n}: a table cell of {len(cell)} characters (at most {MAX_CELL}): {cell[:60]}...")
    for m in re.finditer(r"\.\./[\w./-]+", strip_code(text)):
        line = text.count("\n", 0, m.start()) + 1
        problems.append(f"{name}:{line}: {m.group(0)} is a path outside the repository")
    first = re.search(r"^```\w*\n(.*?)^```", text, re.M | re.S)
    if not first or not all(c in first.group(1) for c in TOP_COMMANDS):
        problems.append(f"{name}: the first code block must hold {' and '.join(TOP_COMMANDS)}")
    check_links(readme, problems)
    for page in sorted((ROOT / "docs").glob("*.md")):
        check_links(page, problems)
    for p in problems:
        print(p)
    if not problems:
        print(f"{name}: {len(raw)} bytes, longest table cell {max((len(c) for _, c in table_cells(text)), default=0)} characters, links resolve")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
