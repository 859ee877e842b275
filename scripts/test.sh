#!/usr/bin/env bash
# The tests of vibrissa, on a fresh machine with the Rust toolchain and python3:
#   1. the Rust workspace (`cargo test --workspace`);
#   2. the Python package: a virtual environment of its own (target/py-venv, or
#      $VIBRISSA_VENV), the package built by maturin and installed with what its tests need
#      (numpy, pandas, dask, pytest, matplotlib, scipy) from the package registry, then
#      pytest (crates/vibrissa-py/tests: against the CLI built here, the examples included).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace
cargo build --release -p vibrissa-cli
venv="${VIBRISSA_VENV:-target/py-venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check "./crates/vibrissa-py[test]"
VIBRISSA_BIN="$PWD/target/release/vibrissa" MPLBACKEND=Agg \
  "$venv/bin/python" -m pytest crates/vibrissa-py/tests -q -p no:cacheprovider
