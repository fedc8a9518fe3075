#!/usr/bin/env bash
# The Python package's tests: makes a virtual environment (target/python-venv,
# kept between runs), installs pytest, pandas, matplotlib and scipy (the closed
# loop test integrates its reference with it) and the package
# itself from crates/multibody-py (built by maturin with the `ci` profile of
# the README's test command, sharing the workspace's target folder), builds
# the `multibody` command the tests compare with and the FMU runtime it
# exports with (target/ci), and
# runs pytest on crates/multibody-py/tests and on the FMU tests
# (crates/multibody-fmu/tests), which check the FMUs with FMPy: when FMPy
# cannot be installed, those skip with a message.
set -euo pipefail
cd "$(dirname "$0")/.."

VENV=${MULTIBODY_PYTHON_VENV:-target/python-venv}
PYTHON=${PYTHON:-python3}
if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
fi
"$VENV/bin/python" -m pip install -q --upgrade pip
"$VENV/bin/python" -m pip install -q "maturin>=1.5,<2" numpy scipy pytest pandas matplotlib pyarrow "dask[distributed]" control
"$VENV/bin/python" -m pip install -q fmpy || echo "FMPy could not be installed: the FMU tests will be skipped"
MATURIN_PEP517_ARGS="--profile ci" "$VENV/bin/python" -m pip install -q ./crates/multibody-py
cargo build --profile ci -q -p multibody-cli -p multibody-fmu
MULTIBODY_COMMAND="${MULTIBODY_COMMAND:-$(pwd)/target/ci/multibody}" \
    "$VENV/bin/python" -m pytest -q crates/multibody-py/tests crates/multibody-fmu/tests
