#!/usr/bin/env bash
# The Python package's tests (python/tests/), the `python` step of scripts/test.sh, runnable on
# its own:
#
#   scripts/test-python.sh [PYTEST ARGS...]          the package from the workspace's test build
#   scripts/test-python.sh --wheel [PYTEST ARGS...]  the package as its README builds it
#                                                    (pip install ./python: maturin, a wheel)
#
# Without --wheel, the package is put together in target/py-pkg/: python/protolink's files and
# the extension that the workspace's `cargo build --profile test` made (scripts/test.sh's test
# build makes it and passes it as $PROTOLINK_PYTHON_SO; run alone, this script builds it).
# That is the wheel's content, built once with the rest of the workspace: maturin would build
# the extension alone, whose dependencies then resolve other features and compile again (about
# three minutes on two cores). With --wheel, maturin builds the wheel with the workspace's
# `pytest` profile and pip installs it into the venv.
#
# Either way the tests run in a venv, target/py-venv, that also sees the user's PyPI packages
# (scripts/setup.sh python), with the `protolink` binary of this checkout as the reference.
# pytest's last line ("N passed, M failed, ...") is what scripts/test.sh adds to its summary.
# Without maturin, pytest, hypothesis, pandas, pyarrow, duckdb, polars or pyspark or java
# (Spark's JVM) the step prints a SKIPPED line and succeeds; under CI=true it fails instead.
set -euo pipefail
cd "$(dirname "$0")/.."

wheel=false
if [ "${1:-}" = --wheel ]; then
  wheel=true
  shift
fi

venv=target/py-venv
if ! { python3 -c 'import maturin, pytest, hypothesis, pandas, pyarrow, duckdb, polars, pyspark' 2>/dev/null \
       && command -v java >/dev/null; }; then
  if [ "${CI:-}" = true ]; then
    echo "FAILED: maturin, pytest, hypothesis, pandas, pyarrow, duckdb, polars or pyspark is missing, or java (scripts/setup.sh python installs them)"
    exit 1
  fi
  echo "SKIPPED python/tests: maturin, pytest, hypothesis, pandas, pyarrow, duckdb, polars or pyspark is missing, or java (scripts/setup.sh python)"
  exit 0
fi
[ -x "$venv/bin/python" ] || python3 -m venv --system-site-packages "$venv"
# The venv's tools first; maturin's PEP 517 backend runs the `maturin` on PATH (a --user
# install puts it in ~/.local/bin).
export PATH="$PWD/$venv/bin:$HOME/.local/bin:$PATH"

protolink=$(scripts/protolink-bin.sh)

if $wheel; then
  # --no-build-isolation: the maturin of scripts/setup.sh builds it (no download per run);
  # --force-reinstall: the package of this checkout, even at the same version.
  # The extension with the workspace's `pytest` profile (opt-level 1, no LTO: minutes less to
  # build than the published wheel's `wheel` profile, which pyproject.toml keeps).
  MATURIN_PEP517_ARGS="--profile pytest" python -m pip install -q --no-build-isolation --force-reinstall --no-deps ./python
  pythonpath=
else
  # Not the installed wheel of an earlier --wheel run: the package below.
  python -m pip uninstall -q -y protolink >/dev/null 2>&1 || true
  so=${PROTOLINK_PYTHON_SO:-}
  if [ -z "$so" ]; then
    # As maturin builds it: an extension module does not link libpython (pyo3 reads this).
    PYO3_BUILD_EXTENSION_MODULE=1 cargo build -q --profile test -p protolink-python
    so="$PWD/${CARGO_TARGET_DIR:-target}/debug/libprotolink_python.so"
  fi
  [ -f "$so" ] || { echo "FAILED: no Python extension at $so"; exit 1; }
  # pyproject.toml's layout: the package python/protolink with the extension as
  # protolink._native (module-name), one file for every CPython from 3.9 on (abi3).
  pkg=target/py-pkg
  rm -rf "$pkg"
  mkdir -p "$pkg"
  cp -R python/protolink "$pkg/protolink"
  cp "$so" "$pkg/protolink/_native.abi3.so"
  pythonpath="$PWD/$pkg"
fi

# From the repository root, so that `import protolink` finds the package built above, not the
# sources in python/protolink (which lack the native module).
PROTOLINK="$protolink" env ${pythonpath:+PYTHONPATH="$pythonpath"} python -m pytest -p no:cacheprovider -q python/tests "$@"
