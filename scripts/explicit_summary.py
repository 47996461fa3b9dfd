#!/usr/bin/env python3
"""Summarises scripts/explicit_study.sh's ladders in one markdown table.

    scripts/explicit_summary.py OUT     (reads OUT/{zoom,full}_{one,all}.csv)

Per view and lighting, per mode, at the ladder's top rung:
  model error  sqrt(max(0, RMSE^2 - RMSE_explicit^2)): the mode's RMSE against the
               explicit reference with the explicit ladder's own RMSE at the same
               spp (its noise and the reference's) taken out;
  time/sample  CPU seconds of that render divided by its spp (all pixels);
  and both relative to hair's.
"""
import csv
import math
import os
import sys

out = sys.argv[1]
cases = [("zoom_one", "zoomed, LED 10"), ("zoom_all", "zoomed, all 25 LEDs"),
         ("full_one", "full view, LED 10"), ("full_all", "full view, all 25 LEDs")]
print("| view, lights | mode | spp | model error | × hair's | CPU s per sample | × hair's |")
print("|---|---|---:|---:|---:|---:|---:|")
for name, label in cases:
    path = os.path.join(out, name + ".csv")
    if not os.path.exists(path):
        continue
    rows = list(csv.DictReader(open(path)))
    top = max(int(r["spp"]) for r in rows)
    at = {r["mode"]: r for r in rows if int(r["spp"]) == top}
    floor = float(at["explicit"]["rmse"]) if "explicit" in at else 0.0
    err = {m: math.sqrt(max(0.0, float(r["rmse"]) ** 2 - floor ** 2)) for m, r in at.items()}
    tps = {m: float(r["cpu_seconds"]) / top for m, r in at.items()}
    for m in at:
        if m == "explicit":
            e, er = f"{float(at[m]['rmse']):.3g} (noise floor)", "—"
        else:
            e = f"{err[m]:.3g}"
            er = f"{err[m] / err['hair']:.2f}" if err.get("hair") else "—"
        tr = f"{tps[m] / tps['hair']:.2f}" if tps.get("hair") else "—"
        print(f"| {label} | {m} | {top} | {e} | {er} | {tps[m]:.3g} | {tr} |")
