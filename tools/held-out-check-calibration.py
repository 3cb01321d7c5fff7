"""Calibration of a held-out check's statistic under a parametric bootstrap, on its own.

The noise scale is estimated from `nt` training errors, `nh` held-out errors are scored under
it, and the bootstrap redraws both at the estimated scale and re-estimates it, as
`geardyn discover` does for M0's held-out check (docs/discover-method.md, step 8). Two
statistics: the full Gaussian deviance (with its log-scale term) and the standardized one
(sum of squared standardized errors). A calibrated test's p-value falls below 0.05 and above
0.95 on about 5% of sets each.

    python3 tools/held-out-check-calibration.py   # about 2 minutes; needs numpy
"""
import numpy as np

rng = np.random.default_rng(1)


def ar1(n, rho):
    """Standard Gaussian errors, AR(1) with lag-one correlation rho."""
    z = np.empty(n)
    z[0] = rng.normal()
    for i in range(1, n):
        z[i] = rho * z[i - 1] + np.sqrt(1 - rho * rho) * rng.normal()
    return z


def statistics(train, held):
    s2 = np.mean(train**2)
    standardized = np.sum(held**2) / s2
    return len(held) * np.log(s2) + standardized, standardized


def study(rho, nt=160, nh=127, b=199, sets=400):
    p = {"full": [], "standardized": []}
    for _ in range(sets):
        train, held = ar1(nt, rho), ar1(nh, rho)
        full, std = statistics(train, held)
        s = np.sqrt(np.mean(train**2))
        reps = np.array([statistics(ar1(nt, rho) * s, ar1(nh, rho) * s) for _ in range(b)])
        p["full"].append((1 + np.sum(reps[:, 0] >= full)) / (b + 1))
        p["standardized"].append((1 + np.sum(reps[:, 1] >= std)) / (b + 1))
    for name, v in p.items():
        v = np.array(v)
        print(f"rho {rho}: {name:12s} p < 0.05 on {np.mean(v < 0.05):.3f}, p > 0.95 on {np.mean(v > 0.95):.3f}")


if __name__ == "__main__":
    study(0.0)
    study(0.6)
