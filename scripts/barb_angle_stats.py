#!/usr/bin/env python3
"""Barb angles of a photo, as read and as generated (docs/analysis.md, "Barb angles
along the shaft"):

  scripts/barb_angle_stats.py LAYOUT.json [FEATHER.fcurves ...]

Readings (layout.json, every feather and side; "confident": confidence >= 0.5):
station-sides read > 90 deg (backward) and < 15 deg (flat), how many of each were
confident, and the jaggedness: median |a_i - a_(i+1)| over neighbouring stations
both confident.
Generated (the .fcurves of `plumage generate --layout`): each barb's root angle to
the shaft (start direction p2 - p0 of its uniform cubic B-spline against the
shaft's control polygon nearest the root), barbs binned by root into 24 windows
along the shaft; windows whose median is under 15 deg with the root before 90 % of
the shaft, barbs over 90 deg, and the median / 90th percentile / largest |difference|
between neighbouring windows' medians."""
import json, math, statistics as st, sys


def readings(path):
    L = json.load(open(path))
    n = confident = back = back_c = flat = flat_c = 0
    jag = []
    for f in L["feathers"]:
        for side in ("left", "right"):
            v = f["vanes"][side]
            a, c = v["barb_angle_deg"], v["barb_angle_confidence"]
            for i in range(len(a)):
                n += 1
                confident += c[i] >= 0.5
                if a[i] > 90: back += 1; back_c += c[i] >= 0.5
                elif a[i] < 15: flat += 1; flat_c += c[i] >= 0.5
                if i + 1 < len(a) and c[i] >= 0.5 and c[i + 1] >= 0.5: jag.append(abs(a[i] - a[i + 1]))
    print(f"readings: {len(L['feathers'])} feathers, {n} station-sides, {confident} confident; "
          f"> 90 deg {back} ({back_c} confident); < 15 deg {flat} ({flat_c} confident); "
          f"jaggedness median {st.median(jag) if jag else float('nan'):.1f} deg over {len(jag)} pairs")


def curves(path):
    out, cur = [], None
    for line in open(path):
        w = line.split("#")[0].split()
        if not w: continue
        if w[0] == "curve":
            cur = {"kind": w[1], "side": w[2], "root": float(w[w.index("root") + 1]), "p": []}
            out.append(cur)
        elif cur is not None:
            try: cur["p"].append((float(w[0]), float(w[1])))
            except ValueError: cur = None
    return out


def generated(paths):
    barbs = back = low = 0
    jag = []
    for path in paths:
        cs = curves(path)
        shaft = next(c for c in cs if c["kind"] == "shaft")["p"]
        for side in ("left", "right"):
            bins = {}
            for c in cs:
                if c["kind"] != "barb" or c["side"] != side or len(c["p"]) < 3: continue
                (x0, y0), (x2, y2) = c["p"][0], c["p"][2]
                dx, dy = x2 - x0, y2 - y0
                if dx == 0 and dy == 0: continue
                mx, my = (x0 + x2) / 2, (y0 + y2) / 2
                k = min(range(len(shaft) - 1), key=lambda i: (shaft[i][0] + shaft[i + 1][0] - 2 * mx) ** 2 +
                        (shaft[i][1] + shaft[i + 1][1] - 2 * my) ** 2)
                tx, ty = shaft[k + 1][0] - shaft[k][0], shaft[k + 1][1] - shaft[k][1]
                cos = (dx * tx + dy * ty) / (math.hypot(dx, dy) * math.hypot(tx, ty))
                a = math.degrees(math.acos(max(-1.0, min(1.0, cos))))
                barbs += 1
                back += a > 90.5
                bins.setdefault(min(23, int(c["root"] * 24)), []).append(a)
            meds = [(b, st.median(v)) for b, v in sorted(bins.items())]
            low += sum(1 for b, m in meds if m < 15 and b < 0.9 * 24)
            jag += [abs(meds[i][1] - meds[i + 1][1]) for i in range(len(meds) - 1) if meds[i + 1][0] == meds[i][0] + 1]
    if jag:
        jag.sort()
        print(f"generated: {len(paths)} feathers, {barbs} barbs, {back} over 90 deg; {low} windows under 15 deg "
              f"away from the tip; jaggedness median {st.median(jag):.2f}, p90 {jag[int(0.9 * len(jag))]:.2f}, "
              f"max {jag[-1]:.1f} deg over {len(jag)} pairs")


if __name__ == "__main__":
    if len(sys.argv) < 2: sys.exit(__doc__)
    readings(sys.argv[1])
    if len(sys.argv) > 2: generated(sys.argv[2:])
