#!/usr/bin/env bash
# The robots the URDF conformance tests read, and Pinocchio's dynamics of
# them: installs Pinocchio (`pin`) and example-robot-data (about 70 URDF
# files with their meshes) from PyPI into a venv (target/robots/venv), links
# the robots folder as target/robots/example-robot-data, and writes
# Pinocchio's golden values of every file it loads, with a fixed and a
# floating base, to target/robots/pinocchio-goldens.json
# (scripts/urdf_goldens.py). The versions are pinned so that the files and
# the values agree. Nothing of it is kept in the repository: the files are
# other people's. Without the network this says so and the tests that need
# it skip with a message.
set -uo pipefail
cd "$(dirname "$0")/.."
OUT=${MULTIBODY_ROBOTS:-target/robots}
mkdir -p "$OUT"
VENV="$OUT/venv"
if [ -f "$OUT/pinocchio-goldens.json" ] && [ -e "$OUT/example-robot-data" ]; then
    echo "robots already fetched in $OUT"
    exit 0
fi
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV" || { echo "warning: no venv: the robot tests will skip"; exit 0; }
if ! "$VENV/bin/python" -m pip install -q pin==4.1.0 example-robot-data==6.0.0; then
    echo "warning: pin and example-robot-data could not be installed from PyPI: the robot tests will skip"
    exit 0
fi
ROBOTS=$(find "$VENV" -type d -path "*share/example-robot-data/robots" | head -1)
[ -d "$ROBOTS" ] || { echo "warning: example-robot-data has no robots folder: the robot tests will skip"; exit 0; }
ln -sfn "$(cd "$ROBOTS" && pwd)" "$OUT/example-robot-data"
"$VENV/bin/python" - "$OUT/example-robot-data" "$OUT/pinocchio-goldens.json.tmp" <<'PY'
import glob, json, os, sys
sys.path.insert(0, "scripts")
from urdf_goldens import goldens
root, out_path = sys.argv[1], sys.argv[2]
out = {}
for path in sorted(glob.glob(os.path.join(root, "**", "*.urdf"), recursive=True)):
    relative = os.path.relpath(path, root)
    for floating in (False, True):
        try:
            out[relative + (" floating" if floating else "")] = goldens(path, floating=floating)
        except BaseException as e:  # Pinocchio's own refusals
            if not floating:
                print(f"Pinocchio does not load {relative}: {str(e).splitlines()[0] if str(e) else e!r}", file=sys.stderr)
json.dump(out, open(out_path, "w"), allow_nan=False, separators=(",", ":"))
print(f"{len(out)} variants (fixed and floating bases) have golden values", file=sys.stderr)
PY
mv "$OUT/pinocchio-goldens.json.tmp" "$OUT/pinocchio-goldens.json"
