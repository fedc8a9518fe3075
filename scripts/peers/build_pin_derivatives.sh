#!/bin/bash
# Builds pin_derivatives.cpp against the Pinocchio headers of the `pin` wheel
# in the peers' venv, with the flags of the peers' native/build_native.sh
# (generic x86-64, no -march=native, as the peers' reported pin_bench_generic).
# Usage: VENV=~/.cache/multibody-peers/venv OUT=/tmp/peers/bin bash build_pin_derivatives.sh
set -e
VENV=${VENV:-$HOME/.cache/multibody-peers/venv}; OUT=${OUT:-/tmp/peers/bin}; mkdir -p "$OUT"
P=$VENV/lib/python3.11/site-packages/cmeel.prefix
HERE=$(cd "$(dirname "$0")" && pwd)
DEFS="-DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 -DNDEBUG"
g++ -std=c++17 -O3 $DEFS -I$P/include -I/usr/include/eigen3 "$HERE/pin_derivatives.cpp" -o "$OUT/pin_derivatives"
