#!/usr/bin/env python3
"""The before/after stage table of bench/smooth.sh (SK_BENCH_BEFORE): lines on stdin
`mesh triangles label report.json` (labels before / after, runs interleaved); one markdown row
per mesh and label with the CPU microseconds per input triangle of each build stage (the least
over the runs) and the shape figures (which must not differ)."""
import json, sys

STAGES = ("normals", "flips", "edge_deletion", "vertex_systems", "fair_points", "patches",
          "repair")
best, shape, order = {}, {}, []
for line in sys.stdin:
    name, nf, label, path = line.split()
    try:
        r = json.load(open(path))
    except Exception:
        continue
    key = (name, label)
    if key not in best:
        order.append(key)
        best[key] = {}
    per = 1e6 / int(nf)
    for k in STAGES:
        if k in r["stage_cpu_seconds"]:
            v = r["stage_cpu_seconds"][k] * per
            best[key][k] = min(v, best[key].get(k, v))
    shape[key] = (r["singular_patches"], r["singular_before_repair"], r["max_overshoot"],
                  r["max_fairness_deg"], r["mean_fairness_deg"], r.get("fair_steps", 0))
cols = [k for k in STAGES if any(k in b for b in best.values())]
print("| mesh | build | " + " | ".join(c.replace("_", " ") for c in cols) +
      " | build us/tri | singular (before repair) | max overshoot | fairness max / mean deg | fair steps |")
print("|" + "---|" * (len(cols) + 7))
for key in order:
    b, sh = best[key], shape[key]
    print(f"| {key[0]} | {key[1]} | " + " | ".join(f"{b.get(c, 0.0):.2f}" for c in cols) +
          f" | {sum(b.values()):.2f} | {sh[0]} ({sh[1]}) | {sh[2]:.4f} | {sh[3]:.2f} / {sh[4]:.3f} | {sh[5]} |")
