#!/usr/bin/env python3
"""Draws book/src/figures/scaling.svg from scaling.csv (the `table/N` medians of
`cargo bench --bench compile`): end-to-end compile time against the number of cans,
log-log, with the collision checks on the same axes. No dependencies beyond Python."""
import csv
import math
import pathlib

here = pathlib.Path(__file__).resolve().parent.parent / "src" / "figures"
rows = list(csv.DictReader(open(here / "scaling.csv")))
n = [int(r["cans"]) for r in rows]
ms = [float(r["median_ms"]) for r in rows]
checks = [int(r["checks"]) for r in rows]

W, H, L, R, T, B = 640, 400, 70, 80, 30, 50
x0, x1 = math.log10(4), math.log10(250)
y0, y1 = math.log10(10), math.log10(10000)
c0, c1 = math.log10(1000), math.log10(1000000)


def px(v):
    return L + (math.log10(v) - x0) / (x1 - x0) * (W - L - R)


def py(v, lo=y0, hi=y1):
    return H - B - (math.log10(v) - lo) / (hi - lo) * (H - T - B)


out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="Helvetica" font-size="12">',
       f'<rect width="{W}" height="{H}" fill="white"/>',
       f'<text x="{W/2}" y="18" text-anchor="middle" font-size="14">declutter compile, N cans around a target (one core)</text>']
for v in [5, 10, 20, 50, 100, 200]:
    out.append(f'<line x1="{px(v):.1f}" y1="{T}" x2="{px(v):.1f}" y2="{H-B}" stroke="#eee"/>')
    out.append(f'<text x="{px(v):.1f}" y="{H-B+16}" text-anchor="middle">{v}</text>')
for v, label in [(10, "10 ms"), (100, "100 ms"), (1000, "1 s"), (10000, "10 s")]:
    out.append(f'<line x1="{L}" y1="{py(v):.1f}" x2="{W-R}" y2="{py(v):.1f}" stroke="#eee"/>')
    out.append(f'<text x="{L-6}" y="{py(v)+4:.1f}" text-anchor="end">{label}</text>')
for v, label in [(1000, "1k"), (10000, "10k"), (100000, "100k"), (1000000, "1M")]:
    out.append(f'<text x="{W-R+6}" y="{py(v, c0, c1)+4:.1f}" fill="#d62728">{label}</text>')
out.append(f'<text x="{W/2}" y="{H-12}" text-anchor="middle">removable cans (log)</text>')
out.append(f'<text x="16" y="{H/2}" transform="rotate(-90 16 {H/2})" text-anchor="middle">median time (log)</text>')
out.append(f'<text x="{W-14}" y="{H/2}" transform="rotate(90 {W-14} {H/2})" text-anchor="middle" fill="#d62728">collision checks (log)</text>')
pts = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in zip(n, ms))
out.append(f'<polyline points="{pts}" fill="none" stroke="#1f77b4" stroke-width="2"/>')
for a, b in zip(n, ms):
    out.append(f'<circle cx="{px(a):.1f}" cy="{py(b):.1f}" r="4" fill="#1f77b4"/>')
pts = " ".join(f"{px(a):.1f},{py(c, c0, c1):.1f}" for a, c in zip(n, checks))
out.append(f'<polyline points="{pts}" fill="none" stroke="#d62728" stroke-width="1.5" stroke-dasharray="5,4"/>')
out.append(f'<line x1="{L+10}" y1="{T+14}" x2="{L+34}" y2="{T+14}" stroke="#1f77b4" stroke-width="2"/>'
           f'<text x="{L+40}" y="{T+18}">time</text>')
out.append(f'<line x1="{L+90}" y1="{T+14}" x2="{L+114}" y2="{T+14}" stroke="#d62728" stroke-dasharray="5,4"/>'
           f'<text x="{L+120}" y="{T+18}">collision checks</text>')
out.append("</svg>")
(here / "scaling.svg").write_text("\n".join(out) + "\n")
