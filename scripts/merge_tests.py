#!/usr/bin/env python3
"""Moves a crate's integration tests (`tests/*.rs`) into one test binary, `tests/it/main.rs`
(issue 35, item 7), as pure renames plus `mod` lines, so that edits made meanwhile to the
files merge (git follows the renames).

Usage, from the repository root: python3 scripts/merge_tests.py CRATE_DIR CRATE_NAME
(for instance `crates/contact-sim contact-sim`, or `. vibrissa` for the facade's tests).

- every `tests/NAME.rs` is `git mv`ed to `tests/it/NAME.rs` and declared `mod NAME;` in the
  new `main.rs`;
- a support module beside the tests (`mod support;` -> `tests/support/mod.rs`, or
  `#[path = "common/x.rs"] mod x;`) is declared once in `main.rs` with a `#[path]`, and the
  files that used it `use crate::NAME;` instead;
- a `#[path]` that leaves `tests/` (`../examples/x.rs`) gets one more `../`;
- insta snapshots `tests/snapshots/NAME__*.snap` move to `tests/it/snapshots/it__NAME__*.snap`
  (the module path `it::NAME`), their `source:` line updated.

Status: run on every crate (2026-11-29; docs/library.md, "Link time"): new integration
tests go straight into `tests/it/` with a `mod` line in `main.rs`; the script refuses to
run where `tests/it/main.rs` exists (it would rewrite it).
"""
import re, subprocess, sys
from pathlib import Path
crate = Path(sys.argv[1]); name = sys.argv[2]
tests = crate / "tests"
files = sorted(p for p in tests.glob("*.rs"))
it = tests / "it"
if (it / "main.rs").exists():
    sys.exit(f"{it}/main.rs exists: add new test files to it by hand (a mod line each)")
it.mkdir(exist_ok=True)
shared = {}   # module name -> path relative to tests/it (declared in main.rs)
def git(*a): subprocess.run(["git", *a], check=True)
for f in files:
    git("mv", str(f), str(it / f.name))
for f in files:
    p = it / f.name
    t = p.read_text()
    # `#[path = "common/x.rs"] mod x;` within tests/: declared once in main.rs
    def sub_path(m):
        path, attrs, mod = m.group(1), m.group(2), m.group(3)
        target = (tests / path).resolve()
        if str(target).startswith(str(tests.resolve()) + "/") and "/" in path and not path.startswith(".."):
            shared.setdefault(mod, "../" + path)
            return f"use crate::{mod};"
        return f'#[path = "../{path}"]\n{attrs}mod\x00 {mod};'
    t = re.sub(r'^#\[path = "([^"]+)"\]\n((?:#\[[^\]]*\]\n)*)mod (\w+);$', sub_path, t, flags=re.M)
    # `mod X;` of a support module beside the tests: declared once in main.rs
    def sub_plain(m):
        mod = m.group(1)
        shared.setdefault(mod, f"../{mod}/mod.rs" if (tests / mod / "mod.rs").exists() else f"../{mod}.rs")
        return f"use crate::{mod};"
    t = re.sub(r"^mod (\w+);$", sub_plain, t, flags=re.M)
    p.write_text(t.replace('mod\x00 ', 'mod '))
snaps = tests / "snapshots"
if snaps.is_dir():
    (it / "snapshots").mkdir(exist_ok=True)
    for s in sorted(snaps.glob("*.snap")):
        new = it / "snapshots" / ("it__" + s.name)
        git("mv", str(s), str(new))
        txt = new.read_text()
        stem = s.name.split("__")[0]
        txt = re.sub(r"^source: (.*)tests/" + stem + r"\.rs$", r"source: \1tests/it/" + stem + ".rs", txt, flags=re.M)
        new.write_text(txt)
mods = "\n".join(f"mod {f.stem};" for f in files)
sh = "".join(f'#[path = "{path}"]\nmod {mod};\n' for mod, path in sorted(shared.items()))
main = f"""//! The integration tests of `{name}`, one binary (issue 35, item 7): one link of the
//! crate and its dependencies instead of one per file. Each former `tests/NAME.rs` is the
//! module `NAME`; run its tests with `cargo test -p {name} --test it NAME::` (a filter
//! after `NAME::` narrows them further, `-- --ignored` as before).

{sh}
{mods}
"""
main = main.replace("\n\n\n", "\n\n")
(it / "main.rs").write_text(main)
print(main)
