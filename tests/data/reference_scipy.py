#!/usr/bin/env python3
"""Independent reference Poincare points of eq. 3a (Kahraman & Singh 1990) from SciPy's DOP853.

Writes tests/data/reference_scipy.json, read by tests/reference_scipy.rs (CI has no Python: only
the committed JSON is used there). Run from the repository root:

    python3 tests/data/reference_scipy.py

Model (design.md section 1, the paper's eq. 5 with k = 1):

    q'' + 2 zeta q' + f(q) = F_m + Omega^2 F_ah sin(Omega s),   s in [0, T], T = 2 pi / Omega,
    f(q) = q - 1 (q > 1), 0 (|q| <= 1), q + 1 (q < -1).

Each forcing period is integrated by scipy.integrate.solve_ivp(method="DOP853") with region
switching: in each region (contact, gap, back contact) the right-hand side is the region's
linear law, smooth through the boundary; a terminal event (direction-aware) stops the solver at
the crossing of q = +-1, and integration restarts on the boundary in the region beyond. So no
step straddles the kink. Every accepted segment is also sampled on its dense output (40 points
per step) to verify that no crossing was skipped inside a step (scipy only checks step ends);
the script stops with an error if one was.

The integration is independent of geardyn: only the model equations are shared.
"""

import datetime
import json
import math
import os
import platform
import sys

import numpy as np
import scipy
from scipy.integrate import solve_ivp

RTOL = 1e-12
ATOL = 1e-14
MAX_STEP = 1.0
SAMPLES_PER_STEP = 40
MAX_CROSSINGS_PER_PERIOD = 10000
OUTPUT = os.path.join("tests", "data", "reference_scipy.json")

CONTACT, GAP, BACK = "contact", "gap", "back_contact"
# Stiffness multiplier kappa and offset c with f(q) = kappa q - c in each region.
LAW = {CONTACT: (1.0, 1.0), GAP: (0.0, 0.0), BACK: (1.0, -1.0)}
# Boundaries of each region: (level, scipy event direction, region beyond).
BOUNDS = {
    CONTACT: [(1.0, -1.0, GAP)],
    BACK: [(-1.0, 1.0, GAP)],
    GAP: [(1.0, 1.0, CONTACT), (-1.0, -1.0, BACK)],
}

CASES = [
    {
        "name": "contact_only",
        "regime": "none",
        "params": {"mean_force": 0.5, "ste_amplitude": 0.05, "zeta": 0.05, "omega": 0.5},
        "x0": [1.5, 0.0],
        "periods": 200,
    },
    {
        "name": "single_sided",
        "regime": "single",
        "params": {"mean_force": 0.1, "ste_amplitude": 0.05, "zeta": 0.05, "omega": 0.9},
        "x0": [0.0, 0.0],
        "periods": 200,
    },
    {
        "name": "double_sided",
        "regime": "double",
        "params": {"mean_force": 0.1, "ste_amplitude": 0.2, "zeta": 0.02, "omega": 0.5},
        "x0": [-0.8, 0.4],
        "periods": 200,
    },
    {
        # The paper's Fig. 2 parameters from rest: settles on the single-sided attractor.
        "name": "paper_fig2_from_rest",
        "regime": "single",
        "params": {"mean_force": 0.1, "ste_amplitude": 0.2, "zeta": 0.02, "omega": 0.5},
        "x0": [0.0, 0.0],
        "periods": 464,
    },
]
RECORD = [1, 10, 50, 100, 200, 464]


def forcing(p, s):
    w = p["omega"]
    return p["mean_force"] + w * w * p["ste_amplitude"] * math.sin(w * s)


def initial_region(p, q, v):
    """Region of a state; on a boundary the direction of motion (then acceleration) decides."""
    dead = q - 1.0 if q > 1.0 else (q + 1.0 if q < -1.0 else 0.0)
    a = forcing(p, 0.0) - 2.0 * p["zeta"] * v - dead
    d = v if v != 0.0 else a
    if q > 1.0 or (q == 1.0 and d > 0.0):
        return CONTACT
    if q < -1.0 or (q == -1.0 and d < 0.0):
        return BACK
    return GAP


def make_event(level, direction):
    def g(_s, y):
        return y[0] - level

    g.terminal = True
    g.direction = direction
    return g


def one_period(p, x, stats):
    """Advance (q, v) by one forcing period; returns the state and the minimum of q seen."""
    period = 2.0 * math.pi / p["omega"]
    zeta = p["zeta"]
    s, y = 0.0, [float(x[0]), float(x[1])]
    region = initial_region(p, y[0], y[1])
    q_min = y[0]
    for _ in range(MAX_CROSSINGS_PER_PERIOD):
        kappa, c = LAW[region]

        def rhs(t, z, kappa=kappa, c=c):
            return [z[1], forcing(p, t) - 2.0 * zeta * z[1] - (kappa * z[0] - c)]

        bounds = BOUNDS[region]
        events = [make_event(level, d) for level, d, _ in bounds]
        sol = solve_ivp(rhs, (s, period), y, method="DOP853", rtol=RTOL, atol=ATOL,
                        max_step=MAX_STEP, events=events, dense_output=True)
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        stats["nfev"] += sol.nfev
        fired = [i for i, te in enumerate(sol.t_events) if len(te) > 0]
        t_stop = sol.t[-1]
        # Verify no crossing was skipped inside a step: q must stay on this region's side of
        # each boundary (strictly inside up to 1e-13) over the dense output of every step.
        ts = np.concatenate([np.linspace(a, b, SAMPLES_PER_STEP, endpoint=False)[1:]
                             for a, b in zip(sol.t[:-1], sol.t[1:])] + [[t_stop]])
        qs = sol.sol(ts)[0]
        q_min = min(q_min, float(np.min(qs)))
        for level, d, _ in bounds:
            # direction -1: region lies above the level; +1: below.
            inside = (qs - level) * (-d)
            if np.any(inside[:-1] < -1e-13):
                raise RuntimeError(f"skipped crossing of q = {level} in region {region} at s ~ {s}")
        if not fired:
            return [float(sol.y[0, -1]), float(sol.y[1, -1])], q_min
        i = fired[0]
        level, _, beyond = bounds[i]
        stats["crossings"] += 1
        s = float(sol.t_events[i][0])
        y = [level, float(sol.y_events[i][0][1])]
        region = beyond
    raise RuntimeError("too many crossings in one period")


def run_case(case):
    p = case["params"]
    x = case["x0"]
    stats = {"nfev": 0, "crossings": 0}
    points = []
    q_min_tail = math.inf
    n = case["periods"]
    for k in range(1, n + 1):
        x, q_min = one_period(p, x, stats)
        if k > n - 10:
            q_min_tail = min(q_min_tail, q_min)
        if k in RECORD:
            points.append({"period": k, "q": x[0], "v": x[1]})
    out = dict(case)
    out["poincare"] = points
    out["q_min_last_10_periods"] = q_min_tail
    out["scipy_rhs_evaluations"] = stats["nfev"]
    out["boundary_crossings"] = stats["crossings"]
    return out


def main():
    results = []
    for case in CASES:
        r = run_case(case)
        print(f"{r['name']}: x = {r['poincare'][-1]}, q_min(last 10) = {r['q_min_last_10_periods']:.6f}, "
              f"nfev = {r['scipy_rhs_evaluations']}", file=sys.stderr)
        results.append(r)
    doc = {
        "provenance": {
            "script": "tests/data/reference_scipy.py",
            "generated_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "python": platform.python_version(),
            "scipy": scipy.__version__,
            "numpy": np.__version__,
            "method": "scipy.integrate.solve_ivp DOP853, region switching at terminal events q = +-1, "
                      "restart on the boundary; dense output sampled to verify no skipped crossing",
            "rtol": RTOL,
            "atol": ATOL,
            "max_step": MAX_STEP,
            "model": "q'' + 2 zeta q' + f(q) = F_m + Omega^2 F_ah sin(Omega s), dead zone f of half-width 1; "
                     "each period integrated over local time s in [0, 2 pi / Omega]",
        },
        "cases": results,
    }
    os.makedirs(os.path.dirname(OUTPUT), exist_ok=True)
    with open(OUTPUT, "w") as fh:
        json.dump(doc, fh, indent=2)
        fh.write("\n")


if __name__ == "__main__":
    main()
