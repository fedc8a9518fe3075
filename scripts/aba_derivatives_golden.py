#!/usr/bin/env python3
"""Golden values of the analytic derivatives of forward dynamics, from Pinocchio.

Writes crates/multibody/tests/golden/aba_derivatives.json: for the peers'
benchmark chain (chain_common.py) with N = 7, 30, 100 links, at its test state
(q_k = 0.1 (k+1), v_k = 0.05 (k+1), tau = 0), and for N = 7 and 30 also at a
second state with every joint away from the first's pattern and a nonzero tau,
Pinocchio's computeABADerivatives(model, data, q, v, tau): ddq_dq, ddq_dv and
Minv (= d ddq / d tau), with the accelerations ddq of pin.aba. Numbers are
written with repr (shortest round trip, full double precision).

The chain is built as the peers' bench_pinocchio.py builds it, from the
constants of chain_common.py, and its accelerations at the test state are
checked against the peers' reference (shared/reference/chain_reference_ddq.json)
when that file is found.

Usage (Pinocchio 4.1.0, the version the peers use):
  python3 -m venv /tmp/pinvenv && /tmp/pinvenv/bin/pip install pin==4.1.0 numpy
  /tmp/pinvenv/bin/python scripts/aba_derivatives_golden.py [PEERS_DIR] [--out FILE]
PEERS_DIR defaults to ../shared/bench/peers (relative to the repository root).
"""
import json
import os
import sys

import numpy as np
import pinocchio as pin

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
args = [a for a in sys.argv[1:] if not a.startswith("--")]
out_path = os.path.join(ROOT, "crates", "multibody", "tests", "golden", "aba_derivatives.json")
if "--out" in sys.argv:
    out_path = sys.argv[sys.argv.index("--out") + 1]
    args.remove(out_path)
peers = os.path.abspath(args[0] if args else os.path.join(ROOT, "..", "shared", "bench", "peers"))
sys.path.insert(0, peers)
from chain_common import COM_X, G, IXX, IYY, IZZ, LINK_LEN, MASS, axis_of, test_state  # noqa: E402


def build_chain(n):
    """The chain of bench_pinocchio.py: revolutes about z, y, z, ... one metre apart."""
    model = pin.Model()
    model.gravity.linear = np.array([0.0, 0.0, -G])
    inertia = pin.Inertia(MASS, np.array([COM_X, 0.0, 0.0]), np.diag([IXX, IYY, IZZ]))
    parent = 0
    for k in range(n):
        placement = pin.SE3(np.eye(3), np.array([0.0 if k == 0 else LINK_LEN, 0.0, 0.0]))
        jm = pin.JointModelRZ() if axis_of(k) == "z" else pin.JointModelRY()
        jid = model.addJoint(parent, jm, placement, f"j{k}")
        model.appendBodyToJoint(jid, inertia, pin.SE3.Identity())
        parent = jid
    return model


def second_state(n):
    """A state unlike the test state's ramp, with torques on every joint."""
    k = np.arange(n, dtype=float)
    q = np.sin(1.3 * k + 0.4) * 1.2
    v = np.cos(0.7 * k + 0.2) * 0.8
    tau = np.sin(2.1 * k + 1.0) * 0.5
    return q, v, tau


def case(n, label, q, v, tau):
    model = build_chain(n)
    data = model.createData()
    ddq = pin.aba(model, data, q, v, tau).copy()
    ddq_dq, ddq_dv, minv = (np.array(m) for m in pin.computeABADerivatives(model, data, q, v, tau))
    # computeMinverse fills the upper triangle; the lower comes from it.
    minv = np.triu(minv) + np.triu(minv, 1).T
    # Cross-checks: Minv against the inverse of crba's M, and the
    # derivatives against central differences of aba (loose: a sanity check).
    m = pin.crba(model, data, q)
    m = np.triu(m) + np.triu(m, 1).T
    assert np.max(np.abs(minv @ m - np.eye(n))) < 1e-8, "Minv is not M^-1"
    h = 1e-6
    for j in range(0, n, max(1, n // 5)):
        e = np.zeros(n)
        e[j] = h
        fd_q = (pin.aba(model, data, q + e, v, tau) - pin.aba(model, data, q - e, v, tau)) / (2 * h)
        fd_v = (pin.aba(model, data, q, v + e, tau) - pin.aba(model, data, q, v - e, tau)) / (2 * h)
        for fd, an in ((fd_q, ddq_dq[:, j]), (fd_v, ddq_dv[:, j])):
            assert np.max(np.abs(fd - an)) < 1e-5 * max(1.0, np.max(np.abs(an))), (n, label, j)
    rows = lambda a: [[float(x) for x in r] for r in a]  # noqa: E731
    return dict(n=n, state=label, q=[float(x) for x in q], v=[float(x) for x in v], tau=[float(x) for x in tau],
                ddq=[float(x) for x in ddq], ddq_dq=rows(ddq_dq), ddq_dv=rows(ddq_dv), Minv=rows(minv))


def main():
    reference = None
    ref_path = os.path.join(peers, "..", "..", "reference", "chain_reference_ddq.json")
    if os.path.exists(ref_path):
        with open(ref_path) as f:
            reference = json.load(f)["chains"]
    cases = []
    for n in (7, 30, 100):
        q, v, tau = test_state(n)
        c = case(n, "test", q, v, tau)
        if reference is not None and str(n) in reference:
            ref = np.array(reference[str(n)]["ddq"])
            assert np.max(np.abs(ref - c["ddq"])) <= 1e-12 * max(1.0, np.max(np.abs(ref))), "chain differs from the reference"
        cases.append(c)
        if n <= 30:
            cases.append(case(n, "second", *second_state(n)))
        print(f"N = {n}: written (max |ddq_dq| = {np.max(np.abs(c['ddq_dq'])):.3g})", file=sys.stderr)
    doc = dict(
        description="Pinocchio computeABADerivatives on the peers' benchmark chain (chain_common.py); "
        "written by scripts/aba_derivatives_golden.py. Matrices are row-major lists of rows; "
        "Minv = d ddq / d tau with its lower triangle filled from the upper.",
        pinocchio=pin.__version__,
        reference_checked=reference is not None,
        cases=cases,
    )
    os.makedirs(os.path.dirname(out_path), exist_ok=True)
    with open(out_path, "w") as f:
        json.dump(doc, f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {out_path} ({os.path.getsize(out_path)} bytes)", file=sys.stderr)


if __name__ == "__main__":
    main()
