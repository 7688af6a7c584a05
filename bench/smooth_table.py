#!/usr/bin/env python3
"""The table of bench/smooth.sh: one line per job on stdin (mesh scheme input.off report.json
[note]), one markdown row per job on stdout."""
import json, math, sys

def even_bound(path):
    """#interior vertices in an even number of faces, from the OFF file, and ceil(#even / 2)"""
    tok = open(path).read().split()
    assert tok[0] == "OFF"
    nv, nf = int(tok[1]), int(tok[2])
    i = 4 + 3 * nv
    faces = [0] * nv
    edges = {}
    for _ in range(nf):
        k = int(tok[i]); f = [int(t) for t in tok[i + 1:i + 1 + k]]; i += 1 + k
        for a in f:
            faces[a] += 1
        for a, b in zip(f, f[1:] + f[:1]):
            e = (min(a, b), max(a, b))
            edges[e] = edges.get(e, 0) + 1
    boundary = set()
    for (a, b), c in edges.items():
        if c == 1:
            boundary.update((a, b))
    even = sum(1 for v in range(nv) if faces[v] and v not in boundary and faces[v] % 2 == 0)
    return nf, even, (even + 1) // 2

rows = []
for line in sys.stdin:
    name, scheme, path, out, *note = line.split(maxsplit=4)
    note = " ".join(note).strip()
    nf, even, bound = even_bound(path)
    try:
        r = json.load(open(out))
    except Exception:
        rows.append((name, scheme, nf, None, note or "no report")); continue
    rows.append((name, scheme, nf, r, note, even, bound))

print("| mesh | scheme | triangles | singular (before repair) | max overshoot (patch) | > 0.5 | fairness max / mean deg | "
      "deleted / bound (ratio) | max normal jump deg | normals | flips | deletion | systems | fair | patches | repair | report | total s | note |")
print("|" + "---|" * 19)
for row in rows:
    name, scheme, nf, r, note = row[:5]
    if r is None:
        print(f"| {name} | {scheme} | {nf} | | | | | | | | | | | | | | | | {note} |"); continue
    even, bound = row[5], row[6]
    st = r['stage_seconds']
    if scheme.startswith("vc1"):
        lb = r['deleted_edges_lower_bound']
        if lb != bound:
            note = (note + " " if note else "") + f"library bound {lb} (#even {r['even_vertices']})"
        ratio = r['deleted_edges'] / bound if bound else 1.0
        dele = f"{r['deleted_edges']} / {bound} ({ratio:.3f})"
    else:
        dele = "-"
    sec = [st.get(k, 0.0) for k in ("normals", "flips", "edge_deletion", "vertex_systems", "fair_points", "patches", "repair", "report")]
    before = f" ({r['singular_before_repair']})" if 'singular_before_repair' in r else ""
    print(f"| {name} | {scheme} | {nf} | {r['singular_patches']}{before} | {r['max_overshoot']:.3f} ({r['max_overshoot_patch']}) | "
          f"{r['overshoot_patches']} | {r['max_fairness_deg']:.1f} / {r['mean_fairness_deg']:.2f} | {dele} | "
          f"{r['max_normal_jump_deg']:.2g} | " + " | ".join(f"{x:.3f}" for x in sec) +
          f" | {r['seconds']:.2f} | {note} |")
