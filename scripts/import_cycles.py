#!/usr/bin/env python3
"""Module import cycles of the workspace's crates.

Usage: python3 scripts/import_cycles.py [--tests] [--strict] [--verbose] [CRATE_DIR ...]
       python3 scripts/import_cycles.py --self-test

Reads every crate's `src/` (default: `crates/*`, `xtask` and the facade at the root), maps
each file to its module (`lib.rs`/`main.rs` the root, `a/mod.rs` and `a.rs` the module `a`,
`a/b.rs` the module `a::b`), and collects the paths each module names: the trees of its `use`
statements (`crate::`, `self::`, `super::` and its own child modules) and the inline paths of
its code (`crate::a::B` in a field type, `super::c::f(..)` in a call). Comments and string
literals are stripped first (an intra-doc link is not an import), and so are the items under
`#[cfg(test)]` (unit tests, test-only modules) and `#[cfg(doc)]` (imports for links) unless
`--tests` is given.

A path resolves to the module that DEFINES its item: it descends through the child modules it
names and follows re-exports (`pub use`, `pub(crate) use`), so `crate::Result` resolving to the
re-export of `error::Result` is an edge to `error`, not to the root. Each resolved module other
than the naming one is an edge; a re-export is an edge of the module that writes it.

A re-export is followed, not counted: a parent's `pub use child::X` is a door to the child's
item, not a dependency of the parent's code (`--strict` counts it as an edge of the parent,
as `cargo modules` does; then a `mod.rs` that re-exports its children and defines items they
use is a cycle). `--self-test` checks the script on small crates written to a temporary
folder: a circle through an inline path, one through a re-export (strict only), one hidden in
a test module (`--tests` only), and a clean crate.

A cycle is a strongly connected component of more than one module. Each is printed with the
lines that make its edges; the exit status is 1 when any crate has one (0 otherwise), so the
script can gate CI.
"""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def strip_comments_and_strings(text):
    """`text` with comments, string and char literals blanked (newlines kept for lines)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif c == "r" and re.match(r'r#*"', text[i:i + 10]) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'r(#*)"', text[i:])
            close = '"' + m.group(1)
            j = text.find(close, i + len(m.group(0)))
            j = n if j < 0 else j + len(close)
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            j += 1
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c == "'":
            # a char literal ('a', '\n', '\u{..}') or a lifetime ('a): only the former is blanked
            m = re.match(r"'(\\[^']{1,10}|[^\\'])'", text[i:])
            if m:
                out.append("' '")
                i += len(m.group(0))
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def item_end(text, i):
    """The end of the item starting at `i`: its `;` or its closing brace, at depth 0."""
    depth = 0
    n = len(text)
    while i < n:
        c = text[i]
        if c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                return i + 1
        elif c == ";" and depth == 0:
            return i + 1
        i += 1
    return n


CFG_SKIP = re.compile(r"#\[cfg\((test|doc)\)\]")


def drop_cfg_items(text, keep_tests):
    """`text` without the items under `#[cfg(test)]` / `#[cfg(doc)]` (newlines kept)."""
    if keep_tests:
        return text
    while True:
        m = CFG_SKIP.search(text)
        if not m:
            return text
        end = item_end(text, m.end())
        text = text[: m.start()] + "\n" * text.count("\n", m.start(), end) + text[end:]


def module_of(src, path):
    """The module path (tuple of names) of the file `path` under `src`."""
    rel = path.relative_to(src).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return tuple(parts)


USE = re.compile(r"\b(pub(\([^)]*\))?\s+)?use\s+([^;]+);")
INLINE = re.compile(r"(?<![\w:])((?:crate|self|super)(?:\s*::\s*\w+)+)")
TEST_MODS = re.compile(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;")


def expand_tree(tree):
    """The paths of a use tree `a::{b, c::{d, e as f}, self}` (aliases dropped)."""
    tree = re.sub(r"\s+", "", tree)
    if tree.startswith("::"):
        tree = tree[2:]
    out = []

    def walk(prefix, t):
        # split t at top-level commas
        parts, depth, cur = [], 0, ""
        for c in t:
            if c == "," and depth == 0:
                parts.append(cur)
                cur = ""
                continue
            depth += c == "{"
            depth -= c == "}"
            cur += c
        if cur:
            parts.append(cur)
        for p in parts:
            if "{" in p:
                head, rest = p.split("{", 1)
                walk(prefix + [s for s in head.split("::") if s], rest[:-1])
            else:
                p = p.split("as")[0] if re.search(r"\bas\b", p) else p
                p = re.sub(r"as\w+$", "", p) if False else p
                segs = [s for s in p.split("::") if s]
                if segs == ["self"]:
                    out.append(prefix)
                elif segs:
                    out.append(prefix + segs)

    walk([], tree)
    return out


def expand_use(stmt):
    """Paths of one `use` statement's tree, aliases (`x as y`) reduced to `x`."""
    stmt = re.sub(r"\s+as\s+\w+", "", stmt)
    return expand_tree(stmt)


class Crate:
    def __init__(self, src, keep_tests):
        self.src = src
        self.files = {}  # module -> (path, text)
        test_only = set()
        for path in sorted(src.rglob("*.rs")):
            rel = path.relative_to(src)
            if rel.parts[0] == "bin" or (len(rel.parts) == 1 and rel.name == "main.rs" and (src / "lib.rs").exists()):
                continue  # binaries are crates of their own
            raw = strip_comments_and_strings(path.read_text())
            mod = module_of(src, path)
            if not keep_tests:
                for m in TEST_MODS.finditer(raw):
                    test_only.add(mod + (m.group(1),))
            self.files[mod] = (path, drop_cfg_items(raw, keep_tests))
        # a test-only module and everything under it
        for mod in list(self.files):
            if any(mod[: len(t)] == t for t in test_only):
                del self.files[mod]
        self.modules = set(self.files)
        # re-exports: (module, name) -> full path (list of segments, absolute)
        self.reexports = {}
        self.uses = {}  # module -> [(absolute path, line, is_reexport)]
        for mod, (path, text) in self.files.items():
            entries = []
            for m in USE.finditer(text):
                line = text.count("\n", 0, m.start()) + 1
                is_pub = m.group(1) is not None
                for p in expand_use(m.group(3)):
                    absolute = self.absolute(mod, p)
                    if absolute is None:
                        continue
                    entries.append((absolute, line, is_pub))
                    if is_pub:
                        name = p[-1] if p[-1] != "*" else None
                        if name:
                            self.reexports[(mod, name)] = absolute
            # inline paths outside use statements
            code = USE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
            for m in INLINE.finditer(code):
                segs = [s.strip() for s in m.group(1).split("::")]
                line = code.count("\n", 0, m.start()) + 1
                absolute = self.absolute(mod, segs)
                if absolute is not None:
                    entries.append((absolute, line, False))
            self.uses[mod] = entries

    def absolute(self, mod, segs):
        """`segs` (a path named in `mod`) made absolute, None for another crate's path."""
        segs = list(segs)
        if not segs:
            return None
        if segs[0] == "crate":
            return segs[1:]
        if segs[0] in ("self", "super"):
            base = list(mod)
            while segs and segs[0] in ("self", "super"):
                if segs[0] == "super":
                    if not base:
                        return None
                    base.pop()
                segs.pop(0)
            return base + segs
        # 2018 paths: a child module of `mod` named directly
        if tuple(mod) + (segs[0],) in self.modules:
            return list(mod) + segs
        return None

    def resolve(self, path, seen=None):
        """The module defining the item at the absolute `path`."""
        seen = seen or set()
        mod = ()
        for i, s in enumerate(path):
            if s == "*":
                return mod
            if mod + (s,) in self.modules:
                mod = mod + (s,)
                continue
            key = (mod, s)
            if key in self.reexports and key not in seen:
                seen.add(key)
                target = self.reexports[key] + path[i + 1 :]
                return self.resolve(target, seen)
            return mod
        return mod

    def edges(self, strict=False):
        """module -> {target module: [lines]}; re-exports count only when `strict`."""
        out = {}
        for mod, entries in self.uses.items():
            for path, line, is_reexport in entries:
                if is_reexport and not strict:
                    continue
                target = self.resolve(path)
                if target != mod and target in self.modules:
                    out.setdefault(mod, {}).setdefault(target, []).append(line)
        return out


def sccs(nodes, edges):
    """Tarjan's strongly connected components."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]
    sys.setrecursionlimit(10000)

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, {}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(comp)

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


def name(mod):
    return "crate" if not mod else "::".join(mod)


def self_test():
    """The script against crates whose cycles are known (module docs)."""
    import tempfile

    cases = {
        # common's type holds accuracy's, accuracy uses common: the circle of issue 35
        "inline": ({
            "lib.rs": "pub mod accuracy;\npub mod common;\npub use common::Settings;\n",
            "common.rs": "pub struct Settings;\npub struct Rec { pub acc: Option<crate::accuracy::Acc> }\n",
            "accuracy.rs": "use crate::Settings; // via the root's re-export\npub struct Acc;\nfn f(_: Settings) {}\n",
        }, {(): 1, ("--strict",): 1, ("--tests",): 1}),
        # a parent that re-exports its child and defines what the child uses
        "facade": ({
            "lib.rs": "pub mod roots;\n",
            "roots/mod.rs": "mod brent;\npub use brent::brent;\npub struct Options;\n",
            "roots/brent.rs": "use super::Options;\n/// [`x`](crate::x) is a doc link, not an import\npub fn brent(_: Options) {}\n",
        }, {(): 0, ("--strict",): 1, ("--tests",): 0}),
        # a cycle only through unit tests
        "tests": ({
            "lib.rs": "pub mod a;\npub mod b;\n",
            "a.rs": "use crate::b::B;\npub struct A(B);\n",
            "b.rs": "pub struct B;\n#[cfg(test)]\nmod tests {\n    use crate::a::A;\n    const S: &str = \"crate::a::A\";\n}\n",
        }, {(): 0, ("--strict",): 0, ("--tests",): 1}),
        "clean": ({
            "lib.rs": "pub mod result;\npub mod common;\npub mod accuracy;\n",
            "result.rs": "pub struct Rec { pub acc: Option<f64> }\n",
            "common.rs": "use crate::result::Rec;\npub fn f(_: &Rec) {}\n",
            "accuracy.rs": "use crate::{common::f, result::Rec};\npub fn g(r: &Rec) { f(r) }\n",
        }, {(): 0, ("--strict",): 0, ("--tests",): 0}),
    }
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, (files, want) in cases.items():
            src = Path(tmp) / name / "src"
            for rel, text in files.items():
                (src / rel).parent.mkdir(parents=True, exist_ok=True)
                (src / rel).write_text(text)
            for flags, n in want.items():
                crate = Crate(src, "--tests" in flags)
                got = [c for c in sccs(crate.modules, crate.edges("--strict" in flags)) if len(c) > 1]
                ok = len(got) == n
                failed += not ok
                print(f"self-test {name} {' '.join(flags) or '(default)'}: {len(got)} cycles, expected {n}: {'ok' if ok else 'FAILED'}")
    return 1 if failed else 0


def main(argv):
    if "--self-test" in argv:
        return self_test()
    keep_tests = "--tests" in argv
    verbose = "--verbose" in argv
    strict = "--strict" in argv
    dirs = [a for a in argv if not a.startswith("--")]
    if not dirs:
        dirs = sorted(str(p) for p in (ROOT / "crates").iterdir() if (p / "src").is_dir())
        dirs += [str(ROOT / "xtask"), str(ROOT)]
    found = 0
    for d in dirs:
        d = Path(d).resolve()
        src = d / "src"
        if not src.is_dir():
            print(f"{d}: no src/ directory", file=sys.stderr)
            return 2
        crate = Crate(src, keep_tests)
        edges = crate.edges(strict)
        n_edges = sum(len(t) for t in edges.values())
        cycles = [sorted(c) for c in sccs(crate.modules, edges) if len(c) > 1]
        label = d.relative_to(ROOT) if d.resolve() != ROOT else Path(".")
        print(f"{label}: {len(crate.modules)} modules, {n_edges} import edges, {len(cycles)} cycles")
        if verbose:
            for m in sorted(edges):
                print(f"  {name(m)} -> {', '.join(name(t) for t in sorted(edges[m]))}")
        for comp in cycles:
            found += 1
            members = set(comp)
            print(f"  cycle: {' <-> '.join(name(m) for m in comp)}")
            for m in comp:
                path = crate.files[m][0].resolve().relative_to(ROOT)
                for t, lines in sorted(edges.get(m, {}).items()):
                    if t in members:
                        at = ", ".join(str(x) for x in lines)
                        print(f"    {name(m)} -> {name(t)}  ({path}:{at})")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
