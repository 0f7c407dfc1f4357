#!/usr/bin/python3
"""The accuracy report as plots: one self-contained HTML page from the CSV
that `pitvol-accuracy CORPUS --html OUT.html` writes beside it
(OUT-results.csv; docs/report.md):

  accuracy_plots.py RESULTS.csv OUT.html

Columns: case,family,method,peer,exact_cm3,volume_cm3,interval_cm3,
error_pct,status (one row per case and method; peer 1 for other programs).
"""
import base64
import csv
import html
import io
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

COLOURS = ["#1565c0", "#c62828", "#2e7d32", "#6a1b9a", "#ef6c00", "#00838f", "#5d4037"]


def num(s):
    try:
        v = float(s)
    except ValueError:
        return math.nan
    return v if math.isfinite(v) else math.nan


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("exact_cm3", "volume_cm3", "interval_cm3", "error_pct"):
            r[k] = num(r[k])
        r["ok"] = r["status"] == "PV_OK"
    return rows


def ordered(values):
    out = []
    for v in values:
        if v not in out:
            out.append(v)
    return out


def png(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, metadata={"Software": None})
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def error_by_family(rows, families, methods):
    """Every case's error, by family, methods and peers side by side."""
    fig, ax = plt.subplots(figsize=(11, 4.8))
    width = 0.8 / max(1, len(methods))
    for mi, m in enumerate(methods):
        xs, ys, xr = [], [], []
        for fi, fam in enumerate(families):
            sel = [r for r in rows if r["method"] == m and r["family"] == fam]
            x0 = fi - 0.4 + width * (mi + 0.5)
            for j, r in enumerate(sel):
                x = x0 + (j - (len(sel) - 1) / 2) * width * 0.15
                (xs if r["ok"] else xr).append(x)
                if r["ok"]:
                    ys.append(r["error_pct"])
        peer = any(r["peer"] == "1" for r in rows if r["method"] == m)
        ax.plot(xs, ys, "o", ms=4, color=COLOURS[mi % len(COLOURS)],
                label=m + (" (peer)" if peer else ""))
        if xr:
            ax.plot(xr, [0.0] * len(xr), "x", ms=6, color=COLOURS[mi % len(COLOURS)])
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xticks(range(len(families)))
    ax.set_xticklabels(families, rotation=30, ha="right")
    ax.set_yscale("symlog", linthresh=0.1)
    ax.set_ylabel("error (%, symmetric log beyond ±0.1)")
    ax.set_title("Error per case by family (x on the zero line: no measurement)")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def mean_error(rows, families, methods):
    """Mean absolute error per family and method."""
    fig, ax = plt.subplots(figsize=(11, 4.2))
    width = 0.8 / max(1, len(methods))
    for mi, m in enumerate(methods):
        vals = []
        for fam in families:
            e = [abs(r["error_pct"]) for r in rows if r["method"] == m and r["family"] == fam and r["ok"]]
            vals.append(np.mean(e) if e else np.nan)
        ax.bar(np.arange(len(families)) - 0.4 + width * (mi + 0.5), vals, width,
               color=COLOURS[mi % len(COLOURS)], label=m)
    ax.set_xticks(range(len(families)))
    ax.set_xticklabels(families, rotation=30, ha="right")
    ax.set_yscale("log")
    ax.set_ylabel("mean |error| (%)")
    ax.set_title("Mean absolute error per family")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def interval_vs_truth(rows, method):
    """Per case of one method: the measured volume's error with its +/-
    interval; the truth is the zero line. Red: the interval missed it."""
    sel = [r for r in rows if r["method"] == method and r["ok"] and math.isfinite(r["interval_cm3"])]
    fig, ax = plt.subplots(figsize=(11, 4.8))
    if not sel:
        ax.text(0.5, 0.5, f"no interval from method {method}", ha="center", transform=ax.transAxes)
        return fig, 0, 0
    err = np.array([r["volume_cm3"] - r["exact_cm3"] for r in sel])
    itv = np.array([r["interval_cm3"] for r in sel])
    held = np.abs(err) <= itv
    x = np.arange(len(sel))
    for ok, colour, label in ((True, "#1565c0", "interval holds the truth"),
                              (False, "#c62828", "interval misses the truth")):
        m = held == ok
        if m.any():
            ax.errorbar(x[m], err[m], yerr=itv[m], fmt="o", ms=4, capsize=2, color=colour,
                        label=f"{label} ({m.sum()})")
    ax.axhline(0, color="k", lw=0.8, label="truth")
    ax.set_xticks(x)
    ax.set_xticklabels([r["case"] for r in sel], rotation=70, ha="right", fontsize=7)
    ax.set_ylabel("measured − exact (cm³)")
    ax.set_title(f"Interval against truth, method {method}: held in {held.sum()} of {len(sel)}")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig, int(held.sum()), len(sel)


def summary_table(rows, methods):
    e = html.escape
    out = ['<table class="summary"><tr><th>method</th><th>cases</th><th>no measurement</th>'
           '<th>mean |error|</th><th>max |error|</th><th>interval holds truth</th></tr>']
    for m in methods:
        sel = [r for r in rows if r["method"] == m]
        ok = [r for r in sel if r["ok"]]
        errs = [abs(r["error_pct"]) for r in ok]
        itv = [r for r in ok if math.isfinite(r["interval_cm3"]) and r["interval_cm3"] > 0]
        held = sum(abs(r["volume_cm3"] - r["exact_cm3"]) <= r["interval_cm3"] for r in itv)
        out.append(
            f'<tr data-method="{e(m)}"><td>{e(m)}</td><td>{len(sel)}</td><td>{len(sel) - len(ok)}</td>'
            f'<td>{np.mean(errs):.3f} %</td><td>{np.max(errs):.3f} %</td>'
            f'<td>{f"{held} of {len(itv)}" if itv else "-"}</td></tr>' if errs else
            f'<tr data-method="{e(m)}"><td>{e(m)}</td><td>{len(sel)}</td><td>{len(sel)}</td>'
            '<td>-</td><td>-</td><td>-</td></tr>')
    out.append("</table>")
    return "\n".join(out)


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    rows = load(argv[0])
    if not rows:
        print(f"accuracy_plots: {argv[0]} holds no results", file=sys.stderr)
        return 3
    families = ordered(r["family"] for r in rows)
    methods = ordered(r["method"] for r in rows)
    first = methods[0]
    figs = [("error", "Error per case by family", error_by_family(rows, families, methods)),
            ("mean", "Mean absolute error per family", mean_error(rows, families, methods))]
    fig, held, n = interval_vs_truth(rows, first)
    figs.append(("interval", "Interval against truth", fig))
    body = ["<h1>pitvol accuracy on the simulated corpus</h1>",
            f"<p>{len(ordered(r['case'] for r in rows))} scans with exactly known volume, "
            f"{len(families)} families; methods: {html.escape(', '.join(methods))}.</p>",
            summary_table(rows, methods)]
    for fid, title, f in figs:
        body.append(f'<figure id="{fid}"><h2>{html.escape(title)}</h2>'
                    f'<img alt="{html.escape(title)}" src="data:image/png;base64,{png(f)}"></figure>')
    css = ("body{font-family:sans-serif;margin:2em auto;max-width:1150px}"
           "table.summary{border-collapse:collapse}table.summary td,table.summary th"
           "{border-bottom:1px solid #ddd;padding:4px 10px;text-align:left}"
           "figure img{max-width:100%;border:1px solid #eee}")
    with open(argv[1], "w", encoding="utf-8") as f:
        f.write("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<title>pitvol accuracy</title><style>{css}</style></head><body>\n"
                + "\n".join(body) + "\n</body></html>\n")
    print(f"accuracy_plots: wrote {argv[1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
