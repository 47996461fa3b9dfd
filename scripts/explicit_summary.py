#!/usr/bin/env python3
"""Summarises scripts/explicit_study.sh's ladders as markdown.

    scripts/explicit_summary.py OUT [REF_SPP]   (reads OUT/{zoom,full}_{one,all}.csv; REF_SPP 1024)

First one table per view and lighting: each mode's RMSE against the explicit
reference per spp (relative MSE and wall seconds per render in brackets). Then one
table of, per view and lighting, per mode, at the ladder's top rung:
  model error  the mode's RMSE against the explicit reference with both noises
               taken out: a render's squared error is M + s/n (M what it converges
               to, s its variance per sample), so the top two rungs n1 < n2 give
               s = (R1^2 - R2^2) / (1/n1 - 1/n2) and M = R2^2 - s/n2; M still holds
               the reference's own noise s_explicit / REF_SPP (s_explicit from the
               explicit ladder the same way), which is taken out:
               sqrt(max(0, M - s_explicit / REF_SPP)). The explicit row's is ~0 when
               the ladders follow 1/n (a check);
  time/sample  CPU seconds of that render divided by its spp (all pixels);
  and both relative to hair's.
"""
import csv
import math
import os
import sys

out = sys.argv[1]
ref_spp = int(sys.argv[2]) if len(sys.argv) > 2 else 1024


def limit_and_variance(rows, mode):
    """M and s of a mode's ladder from its top two rungs (see above)."""
    rungs = sorted((int(r["spp"]), float(r["rmse"])) for r in rows if r["mode"] == mode)
    (n1, r1), (n2, r2) = rungs[-2], rungs[-1]
    s = (r1 * r1 - r2 * r2) / (1 / n1 - 1 / n2)
    return r2 * r2 - s / n2, s
cases = [("zoom_one", "zoomed (0.6 mm), LED 10"), ("zoom_all", "zoomed (0.6 mm), all 25 LEDs"),
         ("full_one", "full view, LED 10"), ("full_all", "full view, all 25 LEDs")]
for name, label in cases:
    path = os.path.join(out, name + ".csv")
    if not os.path.exists(path):
        continue
    rows = list(csv.DictReader(open(path)))
    modes = list(dict.fromkeys(r["mode"] for r in rows))
    print(f"**{label[0].upper() + label[1:]}** — RMSE against the explicit reference "
          "(relative MSE; wall seconds per render)\n")
    print("| spp | " + " | ".join(modes) + " |")
    print("|---:|" + "---:|" * len(modes))
    for spp in sorted({int(r["spp"]) for r in rows}):
        cells = []
        for m in modes:
            r = next(r for r in rows if r["mode"] == m and int(r["spp"]) == spp)
            cells.append(f"{float(r['rmse']):.4g} ({float(r['relative_mse']):.3g}; {float(r['seconds']):.3g} s)")
        print(f"| {spp} | " + " | ".join(cells) + " |")
    print()

print("**Summary**: model error (RMSE extrapolated to infinite spp from the top two rungs, the "
      "reference's noise taken out; scripts/explicit_summary.py) and CPU seconds per sample at the top rung "
      "(the render's CPU time / spp), both also relative to hair's\n")
print("| view, lights | mode | spp | model error | × hair's | CPU s per sample | × hair's |")
print("|---|---|---:|---:|---:|---:|---:|")
for name, label in cases:
    path = os.path.join(out, name + ".csv")
    if not os.path.exists(path):
        continue
    rows = list(csv.DictReader(open(path)))
    top = max(int(r["spp"]) for r in rows)
    at = {r["mode"]: r for r in rows if int(r["spp"]) == top}
    ref_var = limit_and_variance(rows, "explicit")[1] / ref_spp if "explicit" in at else 0.0
    err = {m: math.sqrt(max(0.0, limit_and_variance(rows, m)[0] - ref_var)) for m in at}
    tps = {m: float(r["cpu_seconds"]) / top for m, r in at.items()}
    for m in at:
        e = f"{err[m]:.3g}" + (" (check: ~0)" if m == "explicit" else "")
        er = "—" if m == "explicit" or not err.get("hair") else f"{err[m] / err['hair']:.2f}"
        tr = f"{tps[m] / tps['hair']:.2f}" if tps.get("hair") else "—"
        print(f"| {label} | {m} | {top} | {e} | {er} | {tps[m]:.3g} | {tr} |")
