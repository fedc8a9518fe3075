#!/usr/bin/env bash
# The URDF conformance over real robots: installs Pinocchio (`pin`) and
# example-robot-data (about 70 URDF files, 400 MB) from PyPI into a venv
# (target/urdf-venv), writes Pinocchio's golden values for every file with
# scripts/urdf_goldens.py, and runs the corpus test, which reports how many
# files load and agree and why the others are refused. Not part of CI (the
# download is large); the small robots of crates/multibody-dyad/tests/urdf
# are, with golden values kept in the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${URDF_VENV:-target/urdf-venv}
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/python" -m pip install -q pin example-robot-data
ROBOTS=$("$VENV/bin/python" -c 'import cmeel, os; print(os.path.join(cmeel.__path__[0] + ".prefix", "share", "example-robot-data", "robots"))' 2>/dev/null || true)
[ -d "$ROBOTS" ] || ROBOTS=$(find "$VENV" -type d -path "*share/example-robot-data/robots" | head -1)
GOLDENS=target/urdf-corpus-goldens.json
mapfile -t FILES < <(find "$ROBOTS" -name '*.urdf' | sort)
"$VENV/bin/python" - "$GOLDENS" "${FILES[@]}" <<'PY'
import json, sys
sys.path.insert(0, "scripts")
from urdf_goldens import goldens
out = {}
for path in sys.argv[2:]:
    try:
        out[path] = goldens(path)
    except BaseException as e:  # Pinocchio's own refusals
        print(f"Pinocchio does not load {path}: {str(e).splitlines()[0] if str(e) else e!r}", file=sys.stderr)
json.dump(out, open(sys.argv[1], "w"), allow_nan=False)
print(f"{len(out)} of {len(sys.argv) - 2} files have golden values", file=sys.stderr)
PY
MULTIBODY_URDF_CORPUS=$(pwd)/$GOLDENS cargo test --release -p multibody-dyad --test urdf -- --nocapture corpus
