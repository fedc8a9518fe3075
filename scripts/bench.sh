#!/usr/bin/env bash
# One command for the performance numbers in docs/performance.md:
#   1. our criterion benchmarks, with short warm-up and measurement times:
#      crates/multibody/benches (aba/N, rhs/N, assemble/C, and simulate/NAME
#      where present) and the other crates' benchmarks (the example models in
#      crates/multibody-cli/benches/examples.rs: compile/NAME, simulate/NAME, and
#      stiff_spring/METHOD, the stiff example with the implicit and the explicit method);
#   2. the peers (Pinocchio C++ and MuJoCo C on the same chain) with
#      shared/bench/peers/run.sh --native, in the same run and on the same
#      machine, so that the ratios hold even when absolute times drift; and
#      Pinocchio's computeABADerivatives (scripts/peers/pin_derivatives.cpp)
#      against our aba_derivatives/N; and Pinocchio's ABA on Talos from URDF
#      (scripts/peers/pin_urdf_aba.sh) against our urdf/forward_dynamics_talos;
#   3. the work-precision comparison (our adaptive integrator against
#      MuJoCo's RK4 on the Pendulum and DoublePendulum references):
#      crates/multibody-cli/examples/work_precision.rs, then
#      scripts/work_precision.py with the peers' Python environment.
# The report (markdown) goes to stdout and to target/bench-report.md (the
# benchmark tables alone also to target/bench/table.md); progress and the
# tools' own output go to stderr. Raw data: target/bench/.
#
# Usage: scripts/bench.sh [--quick] [criterion options]
#   --quick  very short measurements, to try the script (numbers not usable)
#   criterion options replace the default --warm-up-time 1 --measurement-time 3
# Environment:
#   PEERS           the peers' directory (default ../shared/bench/peers,
#                   relative to the repository root; MULTIBODY_PEERS works too)
#   PEERS_CACHE     where run.sh keeps its venv and binaries
#                   (default ~/.cache/multibody-peers)
# Takes about 10 minutes on the 2-core development machine (the first run
# longer: builds, and the peers' venv and C/C++ binaries). Run nothing else
# heavy meanwhile.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
QUICK=0
CRITERION_ARGS=()
for arg in "$@"; do
  case "$arg" in
    --quick) QUICK=1 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) CRITERION_ARGS+=("$arg") ;;
  esac
done

say() { echo "bench.sh: $*" >&2; }
die() { say "error: $*"; exit 1; }
trap 'say "error: failed (exit $?) at line $LINENO: $BASH_COMMAND"' ERR

PEERS=${PEERS:-${MULTIBODY_PEERS:-../shared/bench/peers}}
if [ ! -f "$PEERS/run.sh" ]; then
  if [ "$PEERS" = "../shared/bench/peers" ] && [ ! -d "$ROOT/../shared" ]; then
    die "../shared is missing (looked for $(cd "$ROOT/.." && pwd)/shared): the peers' benchmarks live in ../shared/bench/peers next to the repository. Check out the shared directory there, or set PEERS=/path/to/bench/peers."
  fi
  die "the peers' benchmark script $PEERS/run.sh is missing (PEERS=$PEERS, relative to $ROOT). Set PEERS to the directory holding run.sh."
fi
PEERS=$(cd "$PEERS" && pwd)
export PEERS_CACHE=${PEERS_CACHE:-$HOME/.cache/multibody-peers}
PY=$PEERS_CACHE/venv/bin/python
OUT=$ROOT/target/bench
REPORT=$ROOT/target/bench-report.md
mkdir -p "$OUT"

if [ "$QUICK" = 1 ]; then
  [ ${#CRITERION_ARGS[@]} -gt 0 ] || CRITERION_ARGS=(--warm-up-time 0.2 --measurement-time 0.5)
  WP_FLAGS=(--quick)
else
  [ ${#CRITERION_ARGS[@]} -gt 0 ] || CRITERION_ARGS=(--warm-up-time 1 --measurement-time 3)
  WP_FLAGS=()
fi

# The benchmark targets of the workspace, as "package bench" lines.
mapfile -t TARGETS < <(cargo metadata --no-deps --format-version 1 | python3 -c '
import json, sys
for p in json.load(sys.stdin)["packages"]:
    for t in p["targets"]:
        if "bench" in t["kind"]:
            print(p["name"], t["name"])')
[ ${#TARGETS[@]} -gt 0 ] || die "the workspace has no benchmark targets"
grep -q '^multibody ' < <(printf '%s\n' "${TARGETS[@]}") || die "crates/multibody has no benchmark targets"

# Build everything first, so that no compilation runs next to a measurement.
say "building the benchmarks and the work-precision example (release)"
for t in "${TARGETS[@]}"; do
  read -r package bench <<<"$t"
  cargo bench -p "$package" --bench "$bench" --no-run >&2
done
cargo build --release -p multibody-cli --example work_precision >&2

# 1. Ours. Results older than this stamp are ignored (benchmarks that this
# run did not run, e.g. removed ones).
touch "$OUT/started"
sleep 1
for t in "${TARGETS[@]}"; do
  read -r package bench <<<"$t"
  say "running cargo bench -p $package --bench $bench -- ${CRITERION_ARGS[*]}"
  cargo bench -p "$package" --bench "$bench" -- "${CRITERION_ARGS[@]}" >&2
done

# 2. The peers (run.sh also creates their venv when it is missing).
say "running $PEERS/run.sh --native (a few minutes; log in target/bench/peers.log)"
bash "$PEERS/run.sh" --native >"$OUT/peers.csv" 2>"$OUT/peers.log" ||
  { tail -n 20 "$OUT/peers.log" >&2; die "the peers' run.sh failed (log: $OUT/peers.log)"; }
[ -x "$PY" ] || die "the peers' Python ($PY) is missing after run.sh"
PIN_DERIVATIVES=$PEERS_CACHE/bin/pin_derivatives
if [ ! -x "$PIN_DERIVATIVES" ] || [ "$ROOT/scripts/peers/pin_derivatives.cpp" -nt "$PIN_DERIVATIVES" ]; then
  say "building scripts/peers/pin_derivatives.cpp (about a minute)"
  VENV=$PEERS_CACHE/venv OUT=$PEERS_CACHE/bin bash "$ROOT/scripts/peers/build_pin_derivatives.sh" >&2
fi
say "running Pinocchio's computeABADerivatives"
"$PIN_DERIVATIVES" 2>>"$OUT/peers.log" | tail -n +2 >>"$OUT/peers.csv"

if [ -x target/robots/venv/bin/python ]; then
  say "running Pinocchio's ABA on Talos from URDF (scripts/peers/pin_urdf_aba.sh)"
  OUT=$PEERS_CACHE/bin bash "$ROOT/scripts/peers/pin_urdf_aba.sh" 2>>"$OUT/peers.log" >>"$OUT/peers.csv" ||
    say "warning: Pinocchio's ABA on Talos failed (log: $OUT/peers.log)"
else
  say "warning: no robots (scripts/fetch-robots.sh): the URDF comparison is left out"
fi

# 3. Work-precision.
say "running the work-precision example"
"$ROOT/target/release/examples/work_precision" "${WP_FLAGS[@]}" >"$OUT/work_precision.json"
say "running scripts/work_precision.py (MuJoCo RK4)"
WP_STATUS=0
"$PY" "$ROOT/scripts/work_precision.py" --ours "$OUT/work_precision.json" --json "$OUT/work_precision_mujoco.json" \
  --peers-csv "$OUT/peers.csv" "${WP_FLAGS[@]}" >"$OUT/work_precision.md" || WP_STATUS=$?

# The report.
REPORT_STATUS=0
"$PY" "$ROOT/scripts/bench_report.py" "$ROOT/target/criterion" "$OUT/peers.csv" --since "$OUT/started" \
  >"$OUT/table.md" || REPORT_STATUS=$?
# The derivatives of forward dynamics against Pinocchio's, and against our rhs.
"$PY" - "$ROOT/target/criterion" "$OUT/peers.csv" "$OUT/started" >>"$OUT/table.md" <<'PYEOF' || REPORT_STATUS=$?
import csv, json, os, sys
crit, peers, since = sys.argv[1], sys.argv[2], os.path.getmtime(sys.argv[3])
def ours(name):
    path = os.path.join(crit, *name.split("/"), "new", "estimates.json")
    if not os.path.exists(path) or os.path.getmtime(path) < since:
        return None
    return json.load(open(path))["median"]["point_estimate"]
pin = {int(r["N"]): float(r["median_ns"]) for r in csv.DictReader(open(peers))
       if r["tool"] == "pinocchio-c++" and r["what"] == "aba_derivatives"}
us = lambda ns: "–" if ns is None else f"{ns / 1e3:.3g} µs"
ratio = lambda a, b: "–" if a is None or b is None else f"{a / b:.2f}"
print("### Derivatives of forward dynamics (ddq_dq, ddq_dv, M^-1) on the peers' chain\n")
print("Ours: `aba_derivatives/N` = `System::aba_derivatives`; Pinocchio C++ `computeABADerivatives` "
      "(scripts/peers/pin_derivatives.cpp, the peers' generic build flags). Same state, same run.\n")
print("| N | ours | Pinocchio C++ | ours / Pinocchio | ours / our RHS |")
print("|---|---|---|---|---|")
missing = False
for n in (7, 30, 100):
    a, p, r = ours(f"aba_derivatives/{n}"), pin.get(n), ours(f"rhs/{n}")
    missing |= a is None or p is None
    print(f"| {n} | {us(a)} | {us(p)} | {ratio(a, p)} | {ratio(a, r)} |")
print()
if missing:
    print("**Missing from this run: aba_derivatives (ours or Pinocchio's)**\n")
sys.exit(1 if missing else 0)
PYEOF
{
  echo "## Benchmark report"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- commit: $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- crates 2>/dev/null || echo ' (with uncommitted changes under crates/)')"
  echo "- machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
  echo "- $(rustc -V); criterion ${CRITERION_ARGS[*]}; MuJoCo $("$PY" -c 'import mujoco; print(mujoco.__version__)'), Pinocchio $("$PY" -c 'import pinocchio; print(pinocchio.__version__)')"
  if [ "$QUICK" = 1 ]; then echo "- **--quick: short measurements, not for quoting**"; fi
  echo
  cat "$OUT/table.md" "$OUT/work_precision.md"
} >"$REPORT"
cat "$REPORT"
say "report written to $REPORT (raw data in $OUT)"
[ "$REPORT_STATUS" = 0 ] || die "some benchmarks are missing from this run: see the report"
[ "$WP_STATUS" = 0 ] || die "scripts/work_precision.py reported a problem (exit $WP_STATUS): see the report"
