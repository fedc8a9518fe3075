#!/usr/bin/env python3
"""Markdown tables from criterion's estimates and the peers' CSV.

Usage: bench_report.py CRITERION_DIR PEERS_CSV [--since FILE]
  CRITERION_DIR  target/criterion (reads <bench>/new/benchmark.json and
                 estimates.json; the median is reported)
  PEERS_CSV      stdout of shared/bench/peers/run.sh --native
  --since FILE   ignore criterion results older than FILE (stale results of
                 benchmarks that this run did not run)
Standard library only. Called by scripts/bench.sh.
"""

import csv
import json
import os
import sys

NS = [1, 7, 30, 100]


def fmt(ns):
    if ns is None:
        return "–"
    for unit, f in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= f:
            return f"{ns / f:.3g} {unit}"
    return f"{ns:.3g} ns"


def ratio(a, b):
    return "–" if a is None or b is None else f"{a / b:.2f}"


def criterion_medians(root, since):
    """{full_id: median ns} of the benchmarks measured after `since`."""
    out = {}
    for dirpath, _dirs, files in os.walk(root):
        if os.path.basename(dirpath) != "new" or "estimates.json" not in files:
            continue
        est = os.path.join(dirpath, "estimates.json")
        if since is not None and os.path.getmtime(est) < since:
            continue
        with open(os.path.join(dirpath, "benchmark.json")) as f:
            full_id = json.load(f)["full_id"]
        with open(est) as f:
            out[full_id] = json.load(f)["median"]["point_estimate"]
    return out


def peers_rows(path):
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            try:
                rows[(r["tool"], r["what"], int(r["N"]))] = float(r["median_ns"].split()[0])
            except (ValueError, KeyError, AttributeError):
                pass
    return rows


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    since = None
    if "--since" in argv:
        since = os.path.getmtime(argv[argv.index("--since") + 1])
        args.remove(argv[argv.index("--since") + 1])
    crit_dir, peers_csv = args
    ours = criterion_medians(crit_dir, since)
    peers = peers_rows(peers_csv)
    missing = []

    def get(key):
        if key not in ours:
            missing.append(key)
        return ours.get(key)

    md = []
    md.append("### Forward dynamics on the peers' chain (median of one call)\n")
    md.append("Ours: `aba/N` = `Mechanism::forward_dynamics` (ABA: q, v to accelerations), "
              "`rhs/N` = `Mechanism::rhs` (the whole ODE right-hand side). Pinocchio C++ `aba` (the faster "
              "of its two conventions, named), MuJoCo C `mj_forward`. Same chain, same state, same machine, "
              "same run.\n")
    md.append("| N | ours ABA | ours RHS | Pinocchio C++ ABA | MuJoCo C mj_forward | ABA / Pinocchio "
              "| RHS / Pinocchio | ABA / MuJoCo | RHS / MuJoCo |")
    md.append("|---|---|---|---|---|---|---|---|---|")
    for n in NS:
        aba, rhs = get(f"aba/{n}"), get(f"rhs/{n}")
        pin = [(peers[k], conv) for k, conv in ((("pinocchio-c++", "aba", n), "default"),
                                                (("pinocchio-c++", "aba (Convention::WORLD)", n), "WORLD"))
               if k in peers]
        pin_ns, conv = min(pin) if pin else (None, "")
        mj = peers.get(("mujoco-c", "mj_forward", n))
        md.append(f"| {n} | {fmt(aba)} | {fmt(rhs)} | {fmt(pin_ns)}{f' ({conv})' if conv else ''} | {fmt(mj)} "
                  f"| {ratio(aba, pin_ns)} | {ratio(rhs, pin_ns)} | {ratio(aba, mj)} | {ratio(rhs, mj)} |")
    md.append("")
    md.append("Scaling to N = 1000 (the peers stop at 100; 10.0 is linear):\n")
    md.append("| | N = 100 | N = 1000 | N=1000 / N=100 |")
    md.append("|---|---|---|---|")
    for g, label in (("aba", "ours ABA"), ("rhs", "ours RHS")):
        a, b = get(f"{g}/100"), get(f"{g}/1000")
        md.append(f"| {label} | {fmt(a)} | {fmt(b)} | {ratio(b, a)} |")
    md.append("")
    md.append("### Assembly (model to compiled mechanism)\n")
    md.append("| components | time | per component |")
    md.append("|---|---|---|")
    for c in (10, 100, 1000, 10000):
        t = get(f"assemble/{c}")
        md.append(f"| {c} | {fmt(t)} | {fmt(t / c) if t else '–'} |")
    md.append("")
    md.append("### Example models: compile and simulate\n")
    md.append("`compile/NAME`: .dyad file text to a compiled mechanism (parse, lower, assemble); "
              "`simulate/NAME`: the complete simulation its analysis asks for, outputs on the analysis's grid "
              "included (crates/multibody-cli/benches/examples.rs).\n")
    md.append("| model | compile | simulate |")
    md.append("|---|---|---|")
    names = sorted({k.split("/", 1)[1] for k in ours if k.startswith(("simulate/", "compile/"))})
    for name in names:
        md.append(f"| {name} | {fmt(ours.get('compile/' + name))} | {fmt(ours.get('simulate/' + name))} |")
    if not any(k.startswith("simulate/") for k in ours):
        missing.append("simulate/*")
    md.append("")
    md.append("### A stiff model: implicit against explicit\n")
    md.append("`examples/stiff_spring.dyad` (c = 1e8 N/m, d = 1e5 N.s/m, 2 s, 2001 samples, tolerance 1e-6) "
              "with the implicit Rodas4 its analysis asks for and with the explicit default.\n")
    md.append("| Rodas4 | Dormand-Prince 4(5) | Dormand-Prince / Rodas4 |")
    md.append("|---|---|---|")
    rodas, dopri = get("stiff_spring/Rodas4"), get("stiff_spring/DormandPrince45")
    md.append(f"| {fmt(rodas)} | {fmt(dopri)} | {ratio(dopri, rodas)} |")
    md.append("")
    md.append("### Planar against 3-D\n")
    md.append("A 100-link chain of PlanarMechanics revolutes and rods against the same chain of 3-D components "
              "(crates/multibody/benches/planar.rs); `simulate` runs 0.05 s with outputs every 10 ms.\n")
    md.append("| | planar | 3-D | planar / 3-D |")
    md.append("|---|---|---|---|")
    for what in ("rhs", "simulate"):
        p, s = get(f"planar/{what}/planar/100"), get(f"planar/{what}/3d/100")
        md.append(f"| {what} | {fmt(p)} | {fmt(s)} | {ratio(p, s)} |")
    md.append("")
    md.append("### FMU of the double pendulum\n")
    md.append("`crates/multibody-fmu/benches/fmu.rs`: exporting (describe and zip the runtime), and 5 s of "
              "co-simulation through the FMI 2.0 functions (instantiate, 500 steps of 10 ms, four values read "
              "after each) beside the same run as `multibody run` computes it (every signal every 10 ms).\n")
    md.append("| export | co-simulation | run | co-simulation / run |")
    md.append("|---|---|---|---|")
    ex, cs, rn = (get(f"fmu/{k}") for k in ("export/double_pendulum", "cosimulation/double_pendulum_5s",
                                            "run/double_pendulum_5s"))
    md.append(f"| {fmt(ex)} | {fmt(cs)} | {fmt(rn)} | {ratio(cs, rn)} |")
    md.append("")
    md.append("### A robot from URDF: Talos (60 links, 32 moving joints)\n")
    md.append("`crates/multibody-dyad/benches/urdf.rs` on example-robot-data's `talos_reduced.urdf` "
              "(scripts/fetch-robots.sh): importing it (read and check the URDF, write the Dyad model, lower and "
              "assemble), and its forward dynamics at random states, beside Pinocchio's ABA in C++ on the same "
              "file (scripts/peers/pin_urdf_aba.cpp, the peers' generic build flags), same machine, same run.\n")
    md.append("| import | forward dynamics, ours | Pinocchio C++ ABA | ours / Pinocchio |")
    md.append("|---|---|---|---|")
    im, fd = get("urdf/import_talos"), get("urdf/forward_dynamics_talos")
    pin_fd = peers.get(("pinocchio-c++", "aba_urdf", 32))
    md.append(f"| {fmt(im)} | {fmt(fd)} | {fmt(pin_fd)} | {ratio(fd, pin_fd)} |")
    md.append("")
    if missing:
        md.append(f"**Missing from this run: {', '.join(missing)}**\n")
    print("\n".join(md))
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
