#!/bin/bash
# Pinocchio's ABA in C++ on the Talos of example-robot-data, the peer of our
# `urdf/forward_dynamics_talos` benchmark: writes the model with PyPI's `pin`
# from scripts/fetch-robots.sh (target/robots/venv), builds
# pin_urdf_aba.cpp against the same wheel's headers with the flags of the
# peers' generic build (as build_pin_derivatives.sh), and prints its CSV row.
# Usage: OUT=/tmp/peers/bin bash pin_urdf_aba.sh   (from the repository root)
set -euo pipefail
ROBOTS=${MULTIBODY_ROBOTS:-target/robots}
VENV=$ROBOTS/venv; OUT=${OUT:-$ROBOTS/bin}; mkdir -p "$OUT"
[ -x "$VENV/bin/python" ] || { echo "no $VENV: run scripts/fetch-robots.sh" >&2; exit 1; }
P=$(cd "$VENV/lib/python3.11/site-packages/cmeel.prefix" && pwd)
HERE=$(cd "$(dirname "$0")" && pwd)
URDF=$ROBOTS/example-robot-data/talos_data/robots/talos_reduced.urdf
"$VENV/bin/python" -c "import pinocchio as pin, sys; pin.buildModelFromUrdf(sys.argv[1]).saveToBinary(sys.argv[2])" "$URDF" "$OUT/talos.bin"
if [ ! -x "$OUT/pin_urdf_aba" ] || [ "$HERE/pin_urdf_aba.cpp" -nt "$OUT/pin_urdf_aba" ]; then
    echo "building pin_urdf_aba.cpp (about a minute)" >&2
    DEFS="-DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 -DNDEBUG"
    g++ -std=c++17 -O3 $DEFS -I"$P/include" -I/usr/include/eigen3 "$HERE/pin_urdf_aba.cpp" -L"$P/lib" \
        -lpinocchio_default -lboost_serialization -Wl,-rpath,"$P/lib" -o "$OUT/pin_urdf_aba"
fi
"$OUT/pin_urdf_aba" "$OUT/talos.bin"
