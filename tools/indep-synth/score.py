#!/usr/bin/env python3
"""Score geardyn's answers on an indep-synth batch against the hidden truth.

Python 3 standard library only.

    python3 score.py BATCH --commands [--geardyn BIN]   # print the geardyn commands to run
    python3 score.py BATCH [--results DIR] [--json OUT] [--list]

BATCH is a folder written by `indep-synth batch` (BATCH/BATCH.json, BATCH/sets/NAME/,
BATCH/truth/NAME.json). geardyn's output for set NAME is looked for in RESULTS/NAME/
(default RESULTS = BATCH/geardyn):

  validate batches: RESULTS/NAME/out/munro.json    (geardyn validate munro --data BATCH/sets/NAME
                                                     --fits RESULTS/NAME/out --reports RESULTS/NAME/r)
  discover batches: RESULTS/NAME/out/discovery.json (geardyn discover --data BATCH/sets/NAME
                                                     --out RESULTS/NAME/out)
  kubo batches:     RESULTS/NAME/out/kubo.json      (geardyn validate kubo --data BATCH/sets/NAME
                                                     --fits RESULTS/NAME/out --reports RESULTS/NAME/r
                                                     [--validate-args, e.g. "--fit whole"])

(results of the earlier layout, the JSON in RESULTS/NAME/ itself, are read too: geardyn now
refuses an output folder that holds files it did not write, such as the log and timings the
--commands lines keep in RESULTS/NAME/), and, if present, RESULTS/NAME/status (geardyn's exit
status, written by the --commands lines):
a validate fit that fails exits with status 2 and writes nothing; such a set counts as "failed"
(reported, and counted as a miss in the "all sets" coverage line).

Kubo: coverage of the true zeta and omega_n by `zeta_ci95` / `omega_n_hz_ci95` (covariance,
profile), z = (estimate - truth) / `*_std_error`, overall and split by the fit's path
(`parameter_source`: contact part / whole curve), by tooth pairs and by reading-error family; fits
refused (non-zero status, nothing written) counted apart with the reason from log.txt.
`--results` may be given several times (e.g. the default run and a `--fit whole` run): each is
scored, then a side-by-side summary is printed.

Validate: coverage of the truth zeta and omega_n (and of every load's STE) by geardyn's 95%
intervals (inverse Fisher "covariance", "sandwich", "profile"), with Wilson 95% intervals on the
rates, overall and per noise family; the z-scores (estimate - truth) / standard error.

Discover: per set geardyn's answer (`effect`) against the hidden effect: the rate of correct
answers ("none" on null sets, the effect's name on the others) with Wilson intervals, overall,
per hidden effect and per noise family; for a correctly named effect whether its `ci95` contains
the true strength (eps, r2 or F_aT / F_m(design)), and the phase error (the phase of the fitted
(cos, sin) pair `delta`, assumed to be in the generator's convention, against the truth's), and
whether the true phase lies on one of geardyn's 95% phase arcs `phase_wald95_deg` where it gives them,
and on the profile arc `phase_profile95_deg` (or the other basin's Wald arc) with `--phase-profile`.
"""

import argparse
import json
import math
import os
import signal
import sys
from collections import OrderedDict, defaultdict

Z = 1.959963984540054  # 97.5% normal quantile


def wilson(k, n):
    if n == 0:
        return (float("nan"), float("nan"))
    p = k / n
    den = 1 + Z * Z / n
    centre = (p + Z * Z / (2 * n)) / den
    half = Z * math.sqrt(p * (1 - p) / n + Z * Z / (4 * n * n)) / den
    return (max(0.0, centre - half), min(1.0, centre + half))


def rate(k, n):
    if n == 0:
        return "  -/0"
    lo, hi = wilson(k, n)
    return f"{k:3d}/{n:<3d} {100 * k / n:5.1f}%  (Wilson 95% {100 * lo:5.1f}-{100 * hi:5.1f}%)"


def covers(ci, x):
    if ci is None or len(ci) != 2 or ci[0] is None or ci[1] is None:
        return None
    return ci[0] <= x <= ci[1]


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def result_json(d, name):
    """geardyn's output NAME of one set: in d/out (the --commands layout), else in d itself."""
    found = load_json(os.path.join(d, "out", name))
    return found if found is not None else load_json(os.path.join(d, name))


def read_status(d):
    try:
        with open(os.path.join(d, "status")) as f:
            return int(f.read().strip() or "0")
    except (OSError, ValueError):
        return None


def set_names(batch):
    names = sorted(n for n in os.listdir(os.path.join(batch, "sets"))
                   if os.path.isdir(os.path.join(batch, "sets", n)))
    return names


def commands(batch, kind, results, geardyn, extra=""):
    extra = (" " + extra.strip()) if extra and extra.strip() else ""
    for n in set_names(batch):
        data = os.path.join(batch, "sets", n)
        out = os.path.join(results, n)
        if kind == "validate":
            cmd = f"{geardyn} validate munro --data {data} --fits {out}/out --reports {out}/r{extra}"
        elif kind == "kubo":
            cmd = f"{geardyn} validate kubo --data {data} --fits {out}/out --reports {out}/r{extra}"
        else:
            cmd = f"{geardyn} discover --data {data} --out {out}/out{extra}"
        print(f"mkdir -p {out} && {{ date +%s.%N > {out}/t0; {cmd} > {out}/log.txt 2>&1; "
              f"echo $? > {out}/status; date +%s.%N > {out}/t1; }}")


def same_load(a, b):
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b), 1.0)


def truths(batch):
    """(name, truth, noise family) of every set of the batch that has its truth file."""
    for n in set_names(batch):
        truth = load_json(os.path.join(batch, "truth", n + ".json"))
        if truth is None:
            print(f"warning: no truth for {n}", file=sys.stderr)
            continue
        yield n, truth, (truth.get("noise") or {}).get("family", "none")


def score_validate(batch, results, listing):
    rows = []
    for n, truth, fam in truths(batch):
        d = os.path.join(results, n)
        fit = result_json(d, "munro.json")
        st = read_status(d)
        row = {"name": n, "family": fam, "zeta": truth["zeta"], "omega_n_hz": truth["omega_n_hz"],
               "status": st}
        if fit is None:
            row["outcome"] = "failed" if (st is not None and st != 0) else "missing"
            rows.append(row)
            continue
        row["outcome"] = "fit"
        row["zeta_est"] = fit.get("zeta")
        row["omega_est"] = fit.get("omega_n_hz")
        for par, key in (("zeta", "zeta"), ("omega", "omega_n_hz")):
            cis = fit.get(key + "_ci95") or {}
            tv = truth[key]
            for m in ("covariance", "sandwich", "profile"):
                row[f"{par}_{m}"] = covers(cis.get(m), tv)
            se = fit.get(key + "_std_error")
            row[f"{par}_z"] = (fit[key] - tv) / se if se else None
        # STE: design load (ste_design_um_ci95) and every other load (per_load[].ste_um_ci95).
        ste_cov = []
        for tl in truth["loads"]:
            for pl in fit.get("per_load", []):
                if same_load(pl["load_n"], tl["load_n"]):
                    ci = pl.get("ste_um_ci95")
                    if pl.get("fitted") and fit.get("ste_design_um_ci95"):
                        ci = fit["ste_design_um_ci95"].get("covariance", ci)
                    ste_cov.append((tl["load_n"], covers(ci, tl["ste_um"]), pl.get("ste_source")))
        row["ste"] = ste_cov
        rows.append(row)

    n_all = len(rows)
    fitted = [r for r in rows if r["outcome"] == "fit"]
    print(f"validate batch {batch}: {n_all} sets, {len(fitted)} fitted, "
          f"{sum(r['outcome'] == 'failed' for r in rows)} failed (non-zero status, no fit written), "
          f"{sum(r['outcome'] == 'missing' for r in rows)} not run")
    fams = ["all"] + sorted({r["family"] for r in rows})

    def block(title, key):
        print(f"\n{title}")
        for fam in fams:
            sel = [r for r in fitted if fam == "all" or r["family"] == fam]
            vals = [r[key] for r in sel if r.get(key) is not None]
            print(f"  {fam:10s} {rate(sum(vals), len(vals))}")
        if any(r["outcome"] == "failed" for r in rows):
            vals = [bool(r.get(key)) for r in rows if r["outcome"] != "missing"]
            print(f"  {'all, failed fits as misses':10s} {rate(sum(vals), len(vals))}")

    for par, label in (("zeta", "zeta"), ("omega", "omega_n")):
        for m in ("covariance", "sandwich", "profile"):
            block(f"{label}: truth inside geardyn's 95% interval ({m})", f"{par}_{m}")
    print("\nboth zeta and omega_n covered (covariance intervals)")
    for fam in fams:
        sel = [r for r in fitted if fam == "all" or r["family"] == fam]
        vals = [bool(r.get("zeta_covariance")) and bool(r.get("omega_covariance")) for r in sel]
        print(f"  {fam:10s} {rate(sum(vals), len(vals))}")

    print("\nSTE per load: truth inside geardyn's 95% interval")
    by_load = defaultdict(list)
    for r in fitted:
        for load, c, src in r["ste"]:
            if c is not None:
                by_load[load].append(c)
    for load in sorted(by_load, reverse=True):
        v = by_load[load]
        print(f"  {load:8g} N {rate(sum(v), len(v))}")

    print("\nz = (estimate - truth) / standard error (inverse Fisher): mean, SD (1 and 0 if calibrated)")
    for par in ("zeta", "omega"):
        zs = [r[f"{par}_z"] for r in fitted if r.get(f"{par}_z") is not None]
        if len(zs) > 1:
            m = sum(zs) / len(zs)
            sd = math.sqrt(sum((z - m) ** 2 for z in zs) / (len(zs) - 1))
            print(f"  {par:6s} n {len(zs)}, mean {m:+.3f}, SD {sd:.3f}, |z| > 1.96: {sum(abs(z) > Z for z in zs)}")
    if listing:
        print("\nper set: name family truth_zeta est_zeta cov | truth_omega est_omega cov")
        for r in rows:
            if r["outcome"] != "fit":
                print(f"  {r['name']} {r['family']:9s} {r['outcome']} (status {r['status']})")
                continue
            print(f"  {r['name']} {r['family']:9s} {r['zeta']:.5f} {r['zeta_est']:.5f} {str(r['zeta_covariance']):5s} | "
                  f"{r['omega_n_hz']:8.2f} {r['omega_est']:8.2f} {r['omega_covariance']}")
    return rows


def read_seconds(d):
    try:
        with open(os.path.join(d, "t0")) as f0, open(os.path.join(d, "t1")) as f1:
            return float(f1.read()) - float(f0.read())
    except (OSError, ValueError):
        return None


def refusal_reason(d):
    """The error line of a refused fit's log (the first line naming the failure)."""
    try:
        with open(os.path.join(d, "log.txt")) as f:
            lines = [l.strip() for l in f if l.strip()]
    except OSError:
        return "no log"
    for l in lines:
        if "error" in l.lower() or "failed" in l.lower():
            return l
    return lines[-1] if lines else "empty log"


def kubo_path(src):
    if not src:
        return "?"
    if "whole curve" in src:
        return "whole"
    if "contact part" in src:
        return "contact"
    if "rig.toml" in src:
        return "rig.toml"
    return src


def kubo_rows(batch, results):
    rows = []
    for n, truth, fam in truths(batch):
        d = os.path.join(results, n)
        fit = result_json(d, "kubo.json")
        st = read_status(d)
        row = {"name": n, "family": truth.get("noise_family", fam), "pairs": truth["tooth_pairs"],
               "zeta": truth["zeta"], "omega_n_hz": truth["omega_n_hz"], "ste_um": truth["ste_um"],
               "status": st, "seconds": read_seconds(d)}
        if fit is None:
            row["outcome"] = "refused" if (st is not None and st != 0) else "missing"
            if row["outcome"] == "refused":
                row["reason"] = refusal_reason(d)
            rows.append(row)
            continue
        row["outcome"] = "fit"
        row["path"] = kubo_path(fit.get("parameter_source"))
        row["zeta_est"] = fit.get("zeta")
        row["omega_est"] = fit.get("omega_n_hz")
        for par, key in (("zeta", "zeta"), ("omega", "omega_n_hz")):
            cis = fit.get(key + "_ci95") or {}
            tv = truth[key]
            for m in ("covariance", "profile"):
                row[f"{par}_{m}"] = covers(cis.get(m), tv)
                ci = cis.get(m)
                row[f"{par}_{m}_ci"] = ci
            se = fit.get(key + "_std_error")
            row[f"{par}_z"] = (fit[key] - tv) / se if se else None
            row[f"{par}_rel_err"] = (fit[key] - tv) / tv
        rows.append(row)
    return rows


def zstats(vals):
    vals = [v for v in vals if v is not None]
    if len(vals) < 2:
        return "n %d" % len(vals)
    m = sum(vals) / len(vals)
    sd = math.sqrt(sum((v - m) ** 2 for v in vals) / (len(vals) - 1))
    return f"n {len(vals):3d} mean {m:+.2f} SD {sd:.2f}"


def score_kubo(batch, results, listing):
    rows = kubo_rows(batch, results)
    fitted = [r for r in rows if r["outcome"] == "fit"]
    refused = [r for r in rows if r["outcome"] == "refused"]
    missing = [r for r in rows if r["outcome"] == "missing"]
    secs = sorted(r["seconds"] for r in rows if r.get("seconds") is not None)
    print(f"kubo batch {batch}, results {results}: {len(rows)} sets, {len(fitted)} fitted, "
          f"{len(refused)} refused (non-zero status, nothing written), {len(missing)} not run")
    if secs:
        print(f"  wall time per set: median {secs[len(secs) // 2]:.2f} s, max {secs[-1]:.2f} s, total {sum(secs):.0f} s")
    if refused:
        reasons = defaultdict(list)
        for r in refused:
            reasons[r["reason"]].append(r["name"])
        print("  refusals:")
        for k, v in sorted(reasons.items(), key=lambda x: -len(x[1])):
            print(f"    {len(v):3d} x {k[:200]}  ({', '.join(v[:6])}{' ...' if len(v) > 6 else ''})")
    paths = defaultdict(int)
    for r in fitted:
        paths[r["path"]] += 1
    print("  path: " + ", ".join(f"{k} {v}" for k, v in sorted(paths.items())))

    groups = [("all", fitted)]
    for p in sorted({r["path"] for r in fitted}):
        groups.append((f"path {p}", [r for r in fitted if r["path"] == p]))
    for k in sorted({r["pairs"] for r in rows}):
        groups.append((f"{k} pairs", [r for r in fitted if r["pairs"] == k]))
    for f in sorted({r["family"] for r in rows}):
        groups.append((f"{f}", [r for r in fitted if r["family"] == f]))

    def cov(sel, key):
        v = [r[key] for r in sel if r.get(key) is not None]
        return rate(sum(v), len(v))

    for par, label in (("zeta", "zeta"), ("omega", "omega_n")):
        print(f"\n{label}: truth inside geardyn's 95% interval; z = (estimate - truth) / std_error")
        print(f"  {'group':16s} {'covariance':44s} {'profile':44s} z")
        for g, sel in groups:
            print(f"  {g:16s} {cov(sel, par + '_covariance'):44s} {cov(sel, par + '_profile'):44s} "
                  f"{zstats([r[par + '_z'] for r in sel])}")
        if refused:
            allr = [r for r in rows if r["outcome"] != "missing"]
            for m in ("covariance", "profile"):
                v = [bool(r.get(f"{par}_{m}")) for r in allr]
                print(f"  all, refused as misses ({m}): {rate(sum(v), len(v))}")
        rel = [r[par + "_rel_err"] for r in fitted]
        if rel:
            rel_s = sorted(rel)
            print(f"  relative error (estimate - truth) / truth: mean {sum(rel) / len(rel):+.4f}, "
                  f"median {rel_s[len(rel_s) // 2]:+.4f}")
    print("\nboth zeta and omega_n covered")
    for g, sel in groups:
        for m in ("covariance", "profile"):
            v = [bool(r.get(f"zeta_{m}")) and bool(r.get(f"omega_{m}")) for r in sel]
            print(f"  {g:16s} {m:10s} {rate(sum(v), len(v))}")
    if listing:
        print("\nper set: name pairs family path | zeta truth est cov prof z | omega truth est cov prof z")
        for r in rows:
            if r["outcome"] != "fit":
                print(f"  {r['name']} {r['pairs']:2d} {r['family']:9s} {r['outcome']} (status {r['status']}) "
                      f"zeta {r['zeta']:.4f} omega {r['omega_n_hz']:.0f}: {r.get('reason', '')[:120]}")
                continue
            zz = r["zeta_z"] if r["zeta_z"] is not None else float("nan")
            oz = r["omega_z"] if r["omega_z"] is not None else float("nan")
            print(f"  {r['name']} {r['pairs']:2d} {r['family']:9s} {r['path']:7s} | {r['zeta']:.4f} {r['zeta_est']:.4f} "
                  f"{str(r['zeta_covariance']):5s} {str(r['zeta_profile']):5s} {zz:+6.2f} | {r['omega_n_hz']:7.1f} "
                  f"{r['omega_est']:7.1f} {str(r['omega_covariance']):5s} {str(r['omega_profile']):5s} {oz:+6.2f}")
    return rows


def kubo_side_by_side(batch, all_rows):
    print("\n==== side by side ====")
    hdr = "  " + f"{'':34s}" + "".join(f"{os.path.basename(os.path.normpath(r))[:28]:>30s}" for r, _ in all_rows)
    print(hdr)

    def line(label, fn):
        print("  " + f"{label:34s}" + "".join(f"{fn(rows):>30s}" for _, rows in all_rows))

    def c(key, sel=lambda r: True):
        def f(rows):
            v = [r[key] for r in rows if r["outcome"] == "fit" and sel(r) and r.get(key) is not None]
            if not v:
                return "-"
            lo, hi = wilson(sum(v), len(v))
            return f"{sum(v)}/{len(v)} {100 * sum(v) / len(v):.1f}% [{100 * lo:.0f}-{100 * hi:.0f}]"
        return f

    def zf(key):
        def f(rows):
            v = [r[key] for r in rows if r["outcome"] == "fit" and r.get(key) is not None]
            if len(v) < 2:
                return "-"
            m = sum(v) / len(v)
            sd = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1))
            return f"{m:+.2f} / {sd:.2f}"
        return f

    line("fitted / refused", lambda rows: f"{sum(r['outcome'] == 'fit' for r in rows)} / {sum(r['outcome'] == 'refused' for r in rows)}")
    line("path contact / whole", lambda rows: f"{sum(r.get('path') == 'contact' for r in rows)} / {sum(r.get('path') == 'whole' for r in rows)}")
    for par, label in (("zeta", "zeta"), ("omega", "omega_n")):
        line(f"{label} covariance", c(f"{par}_covariance"))
        line(f"{label} profile", c(f"{par}_profile"))
        line(f"{label} z mean / SD", zf(f"{par}_z"))


def ang_diff_deg(a, b):
    d = (a - b + math.pi) % (2 * math.pi) - math.pi
    return abs(math.degrees(d))


def score_discover(batch, results, listing):
    rows = []
    for n, truth, fam in truths(batch):
        eff = truth["effect_name"]
        d = os.path.join(results, n)
        disc = result_json(d, "discovery.json")
        row = {"name": n, "family": fam, "hidden": eff, "strength": truth.get("effect_strength"),
               "phase": (truth.get("effect") or {}).get("phase_rad"), "status": read_status(d)}
        if disc is None:
            row["answer"] = None
            rows.append(row)
            continue
        ans = disc.get("effect")
        row["answer"] = ans
        row["ambiguous_with"] = disc.get("ambiguous_with")
        row["closest"] = disc.get("closest_candidate")
        row["correct"] = ans == eff
        if eff != "none" and ans == eff:
            cand = next((c for c in disc.get("candidates", []) if c.get("name") == eff), None)
            if cand is not None:
                row["estimate"] = cand.get("estimate")
                row["ci95"] = cand.get("ci95")
                row["covered"] = covers(cand.get("ci95"), row["strength"])
                delta = cand.get("delta")
                if delta and len(delta) >= 2 and row["phase"] is not None:
                    ph = math.atan2(delta[1], delta[0])
                    row["phase_est"] = ph
                    row["phase_err_deg"] = ang_diff_deg(ph, row["phase"])
                arcs = cand.get("phase_wald95_deg")
                if arcs and row["phase"] is not None:
                    t = math.degrees(row["phase"])
                    on = lambda arc: (t - arc[0]) % 360.0 <= arc[1] - arc[0]
                    row["phase_covered"] = any(on(a) for a in arcs)
                    profile = cand.get("phase_profile95_deg")
                    if profile:
                        row["phase_profile_covered"] = on(profile) or any(on(a) for a in arcs[1:])
        rows.append(row)

    done = [r for r in rows if r["answer"] is not None]
    print(f"discover batch {batch}: {len(rows)} sets, {len(done)} with a discovery.json, "
          f"{len(rows) - len(done)} without")
    print("\ncorrect answers (\"none\" on null sets, the hidden effect's name otherwise)")
    print(f"  {'all':26s} {rate(sum(r['correct'] for r in done), len(done))}")
    effects = sorted({r["hidden"] for r in rows})
    for eff in effects:
        sel = [r for r in done if r["hidden"] == eff]
        print(f"  hidden {eff:19s} {rate(sum(r['correct'] for r in sel), len(sel))}")
        for fam in sorted({r["family"] for r in sel}):
            s2 = [r for r in sel if r["family"] == fam]
            print(f"    {fam:24s} {rate(sum(r['correct'] for r in s2), len(s2))}")
        answers = defaultdict(int)
        for r in sel:
            answers[r["answer"]] += 1
        print(f"    answers: " + ", ".join(f"{a} {k}" for a, k in sorted(answers.items(), key=lambda x: -x[1])))
    null = [r for r in done if r["hidden"] == "none"]
    if null:
        fp = sum(r["answer"] != "none" for r in null)
        print(f"\nfalse-positive rate on null sets (any answer but \"none\"): {rate(fp, len(null))}")
        named = sum(r["answer"] not in ("none", "unexplained", "ambiguous") for r in null)
        print(f"  of which an effect named: {named}")
    print("\ncorrectly named effect: true strength inside geardyn's ci95")
    for eff in effects:
        if eff == "none":
            continue
        sel = [r for r in done if r["hidden"] == eff and r["correct"] and r.get("covered") is not None]
        print(f"  {eff:26s} {rate(sum(r['covered'] for r in sel), len(sel))}")
        errs = sorted(r["phase_err_deg"] for r in sel if r.get("phase_err_deg") is not None)
        if errs:
            print(f"    phase error (deg): median {errs[len(errs) // 2]:.1f}, max {errs[-1]:.1f}")
        arcs = [r["phase_covered"] for r in sel if r.get("phase_covered") is not None]
        if arcs:
            print(f"    true phase on a phase_wald95_deg arc: {rate(sum(arcs), len(arcs))}")
        prof = [r["phase_profile_covered"] for r in sel if r.get("phase_profile_covered") is not None]
        if prof:
            print(f"    true phase on the phase_profile95_deg arc: {rate(sum(prof), len(prof))}")
    if listing:
        print("\nper set: name family hidden strength phase(deg) -> answer [estimate ci95 covered phase_err]")
        for r in rows:
            ph = f"{math.degrees(r['phase']):6.1f}" if r.get("phase") is not None else "     -"
            extra = ""
            if r.get("estimate") is not None:
                ci = r.get("ci95") or [float("nan")] * 2
                extra = f" [{r['estimate']:.4f} ({ci[0]:.4f}, {ci[1]:.4f}) {r.get('covered')} {r.get('phase_err_deg', float('nan')):.1f} deg"
                if r.get("phase_covered") is not None:
                    extra += f" on arc {r['phase_covered']}"
                if r.get("phase_profile_covered") is not None:
                    extra += f" on profile arc {r['phase_profile_covered']}"
                extra += "]"
            if r.get("ambiguous_with"):
                extra += f" ambiguous_with {r['ambiguous_with']}"
            if r.get("closest"):
                extra += f" closest {r['closest']}"
            print(f"  {r['name']} {r['family']:9s} {r['hidden']:24s} {r['strength'] if r['strength'] is not None else '-'} {ph} -> {r['answer']}{extra}")
    return rows


def main():
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # quiet under `| head`
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("batch", help="batch folder written by indep-synth batch")
    ap.add_argument("--results", action="append",
                    help="folder with geardyn's output per set (default BATCH/geardyn); kubo: may be given more than once")
    ap.add_argument("--validate-args", default="",
                    help="with --commands: extra arguments for each geardyn command (e.g. \"--fit whole\")")
    ap.add_argument("--commands", action="store_true", help="print the geardyn commands to run, one per set")
    ap.add_argument("--geardyn", default="geardyn", help="geardyn binary for --commands")
    ap.add_argument("--json", help="also write the per-set rows to this JSON file")
    ap.add_argument("--list", action="store_true", help="print one line per set")
    a = ap.parse_args()
    meta = load_json(os.path.join(a.batch, "BATCH.json"))
    if meta is None:
        sys.exit(f"{a.batch}: no BATCH.json (not an indep-synth batch)")
    kind = meta["kind"]
    results_list = a.results or [os.path.join(a.batch, "geardyn")]
    results = results_list[0]
    if a.commands:
        commands(a.batch, kind, results, a.geardyn, a.validate_args)
        return
    if kind == "kubo":
        all_rows = []
        for res in results_list:
            all_rows.append((res, score_kubo(a.batch, res, a.list)))
            print()
        if len(all_rows) > 1:
            kubo_side_by_side(a.batch, all_rows)
        if a.json:
            with open(a.json, "w") as f:
                json.dump({res: rows for res, rows in all_rows}, f, indent=1)
        return
    rows = score_validate(a.batch, results, a.list) if kind == "validate" else score_discover(a.batch, results, a.list)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
