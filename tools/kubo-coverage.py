#!/usr/bin/env python3
"""Coverage of `validate kubo`'s 95% intervals on seeded synthetic envelopes.

Each seed is a set made by `geardyn synth kubo` (8 tooth pairs, 4% relative scatter; extra
arguments such as `--zeta 0.15 --omega-n-hz 2800` go to synth), fitted by `geardyn validate
kubo`; the script counts how often the covariance (Fisher) and profile intervals of zeta and
omega_n hold the truth, with Wilson 95% intervals, and the standard deviation of the
standardized errors (estimate - truth) / standard error, which is 1 when the standard errors
are right. Sets whose fit is refused are counted and their reasons listed. The counts are
given over all fitted sets and for each path that fitted them (the contact part of the curve,
or the whole curve when the contact part does not determine zeta).

    python3 tools/kubo-coverage.py 200 --zeta 0.15 --omega-n-hz 2800
    python3 tools/kubo-coverage.py 200 --zeta 0.06 --omega-n-hz 2200 --dop853-rtol 1e-9
    GEARDYN=target/release/geardyn python3 tools/kubo-coverage.py 200
"""
import collections
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile


def wilson(k, n, z=1.96):
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    binary = os.environ.get("GEARDYN", "target/release/geardyn")
    seeds = int(sys.argv[1])
    extra = sys.argv[2:]
    options = dict(zip(extra[::2], extra[1::2]))
    zeta = float(options.get("--zeta", 0.1))
    omega = float(options.get("--omega-n-hz", 2500.0))
    inside = collections.Counter()
    refused = collections.Counter()
    paths = collections.Counter()
    z_zeta, z_omega = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, seeds + 1):
            d = os.path.join(tmp, f"s{seed}")
            subprocess.run([binary, "synth", "kubo", "--out", d, "--seed", str(seed)] + extra,
                           check=True, capture_output=True)
            r = subprocess.run([binary, "validate", "kubo", "--data", d, "--fits", d + "/f",
                                "--reports", d + "/r"], capture_output=True, text=True)
            if r.returncode != 0:
                reason = r.stderr.strip().split("failed: ")[-1]
                refused[re.sub(r"\d[\d.e+-]*", "#", reason)] += 1
                continue
            fit = json.load(open(os.path.join(d, "f", "kubo.json")))
            path = "whole curve" if "whole curve" in fit["parameter_source"] else "contact part"
            paths[path] += 1
            for name, truth in (("zeta", zeta), ("omega_n_hz", omega)):
                for kind in ("covariance", "profile"):
                    lo, hi = fit[name + "_ci95"][kind]
                    for group in ("all", path):
                        inside[(group, name, kind)] += lo <= truth <= hi
            z_zeta.append((fit["zeta"] - zeta) / fit["zeta_std_error"])
            z_omega.append((fit["omega_n_hz"] - omega) / fit["omega_n_hz_std_error"])
    n = len(z_zeta)
    print(f"truth zeta {zeta}, omega_n {omega} Hz: {n} of {seeds} sets fitted")
    for reason, count in refused.items():
        print(f"  refused {count}: {reason}")
    for (group, name, kind), k in sorted(inside.items()):
        m = n if group == "all" else paths[group]
        lo, hi = wilson(k, m)
        print(f"  {group}: {name} {kind}: {k}/{m} = {100 * k / m:.1f}% "
              f"(Wilson {100 * lo:.0f}-{100 * hi:.0f}%)")
    print(f"  standardized errors: sd {statistics.stdev(z_zeta):.2f} (zeta), "
          f"{statistics.stdev(z_omega):.2f} (omega_n)")


if __name__ == "__main__":
    main()
