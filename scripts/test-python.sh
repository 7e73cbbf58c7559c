#!/usr/bin/env bash
# The Python package's tests (python/tests/), the `python` step of scripts/test.sh, runnable on
# its own: builds the package the way its README says (pip install ./python, maturin) into a
# venv, target/py-venv, that also sees the user's PyPI packages (scripts/setup.sh python), and
# runs pytest with the `protolink` binary of this checkout as the reference.
#
# pytest's last line ("N passed, M failed, ...") is what scripts/test.sh adds to its summary.
# Without maturin, pytest, hypothesis, pandas, pyarrow, duckdb, polars, pyspark or java (Spark's
# JVM) the step prints a SKIPPED line and succeeds; under CI=true it fails instead.
set -euo pipefail
cd "$(dirname "$0")/.."

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
# --no-build-isolation: the maturin of scripts/setup.sh builds it (no download per run);
# --force-reinstall: the package of this checkout, even at the same version.
# The extension with the workspace's `pytest` profile (opt-level 1, no LTO: minutes less to
# build than the published wheel's `wheel` profile, which pyproject.toml keeps).
MATURIN_PEP517_ARGS="--profile pytest" python -m pip install -q --no-build-isolation --force-reinstall --no-deps ./python

# From the repository root, so that `import protolink` finds the installed package, not the
# sources in python/protolink (which lack the native module).
PROTOLINK="$protolink" python -m pytest -p no:cacheprovider -q python/tests "$@"
