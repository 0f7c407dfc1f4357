#!/usr/bin/python3
"""pitvol-report: one self-contained HTML page (and optionally a PDF) that
shows a measurement: the result, area against height, the outline at
several heights, the coverage map and a side view (docs/report.md).

  pitvol-report FILE|DIR --out report.html [--pdf report.pdf]
                [--pitvol PATH] [--mass-g G] [--moisture-percent W]
                [-- pitvol measure options ...]

FILE: a scan; `pitvol measure FILE --export TMPDIR` runs first (options
after `--` go to it, e.g. --units m). DIR: an existing export.
Exit codes: 0 page written (also for a refused measurement: the page says
why), 2 usage, 3 the scan or the export cannot be read, 5 internal error.
"""
import argparse
import base64
import errno
import html
import io
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import report_data  # noqa: E402
import report_plots  # noqa: E402

# Result block rows: (JSON key, label, format, unit). The page carries each
# value exactly (data-value, repr) besides the rounded text, so a test can
# compare it with `pitvol measure --json`.
# What layers_used/layers_rejected count depends on the method: the surface
# model's wall bins, the per-layer methods' 0.5 mm layers.
SURFACE_LABELS = {"layers_used": "Wall bins seen", "layers_rejected": "Wall bins rejected"}


def row_label(result, key, label):
    if result.get("method") == "surface":
        return SURFACE_LABELS.get(key, label)
    return label


RESULT_ROWS = [
    ("volume_cm3", "Volume", "{:.1f}", "cm³"),
    ("interval_cm3", "Interval (±)", "{:.1f}", "cm³"),
    ("depth_mm", "Depth (floor plane to rim)", "{:.1f}", "mm"),
    ("tilt_deg", "Tilt of the scan", "{:.2f}", "deg"),
    ("unseen_share", "Volume over unseen wall", "{:.2%}", ""),
    ("layers_used", "Layers used", "{:d}", ""),
    ("layers_rejected", "Layers rejected", "{:d}", ""),
    ("points_in", "Points read", "{:d}", ""),
    ("points_used", "Points used", "{:d}", ""),
]

# A page an office files: A4 portrait, the data sheet first, the
# project's units (mm, cm³, g, kg/m³, %) throughout.
CSS = """
@page { size: A4 portrait; margin: 15mm; }
body { font-family: "DejaVu Sans", sans-serif; margin: 1.5em auto; max-width: 180mm; color: #212121;
       font-size: 10.5pt; }
h1 { font-size: 1.45em; margin: 0 0 0.1em 0; border-bottom: 2px solid #212121; padding-bottom: 0.2em; }
h2 { font-size: 1.15em; margin-top: 1.4em; border-bottom: 1px solid #9e9e9e; }
.sub { color: #616161; margin-top: 0.2em; }
.file { color: #616161; font-family: monospace; }
table.sheet { border-collapse: collapse; width: 100%; margin: 0.8em 0; }
table.sheet th, table.sheet td { border: 1px solid #757575; padding: 4px 8px; text-align: left;
                                 vertical-align: top; }
table.sheet th { width: 42%; font-weight: normal; background: #fafafa; }
table.sheet tr.group th { background: #e0e0e0; font-weight: bold; }
.range { color: #424242; }
.blank { color: #9e9e9e; }
.verdict { font-size: 1.3em; padding: 0 0.4em; }
.verdict.pass { color: #1b5e20; border: 2px solid #1b5e20; }
.verdict.fail { color: #b71c1c; border: 2px solid #b71c1c; }
.verdict.undecided { color: #e65100; border: 2px solid #e65100; }
.decide { font-size: 0.9em; }
table.sign { width: 100%; margin: 1.2em 0 0.4em 0; border-collapse: collapse; }
table.sign td { width: 50%; padding: 2px 8px; }
table.sign tr.line td { height: 2.2em; border-bottom: 1px solid #212121; }
.small { font-size: 0.8em; color: #616161; }
table.result { border-collapse: collapse; margin: 1em 0; }
table.result td, table.result th { border-bottom: 1px solid #e0e0e0; padding: 3px 10px; text-align: left; }
.big { font-size: 1.4em; font-weight: bold; }
.refused { background: #ffebee; border: 1px solid #c62828; padding: 0.8em; }
.warn { color: #e65100; }
figure { margin: 1.2em 0; page-break-inside: avoid; }
figure img { max-width: 100%; border: 1px solid #eeeeee; }
figcaption { color: #424242; font-size: 0.9em; }
.note { color: #757575; font-style: italic; }
@media print { body { margin: 0; max-width: none; } #sheet { page-break-after: always; } }
"""

CAPTIONS = {
    "area": "Section area of the pit per 0.5 mm of height. Blue: layers the volume rests on; "
            "red crosses: layers rejected (paper) or mostly unseen (surface); orange bands: "
            "wall the scan did not see, bridged from around it.",
    "outline": "The fitted wall at five heights (10 % to 90 % of the depth) over the scan's "
               "points within a bin's height of it; orange where that wall was bridged.",
    "coverage": "Every wall bin of the surface model by angle around the pit's axis and "
                "height: green seen, orange not seen (bridged, counted in the interval); right: "
                "the share seen per height band, as in the result's coverage.",
    "pit3d": "The reconstructed pit: the surface model's wall around its axis (blue where the "
             "scan saw it, orange where it was bridged from the wall around it and counted in "
             "the interval) over the floor at z = 0, from the floor plane to the rim.",
    "side": "The levelled cloud seen from the side (x and y through the axis): the floor plane "
            "at z = 0, the rim the volume stops at, and the fitted wall in that plane.",
}


def fail(code, msg):
    print(f"pitvol-report: {msg}", file=sys.stderr)
    sys.exit(code)


# Plausible ranges of the numbers a user types: the numbers of
# lib/density/include/pitvol/density.h (tests/report checks they agree),
# so the report refuses what the board refuses.
RANGES = {
    "mass-g": (50.0, 100000.0, "g", "wet mass of the excavated soil"),
    "moisture-percent": (0.0, 100.0, "%", "water content, % of the dry mass"),
    "max-dry-density-kg-m3": (1000.0, 2800.0, "kg/m3",
                              "Proctor maximum dry density; a value in g/cm3 times 1000"),
    "required-compaction-percent": (50.0, 110.0, "%",
                                    "relative compaction the specification requires"),
}
DECIMAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


def typed_number(option):
    """An argparse type: a decimal number (not 0x10, 1,5, inf or nan)
    inside the option's plausible range; the refusal names the range."""
    lo, hi, unit, what = RANGES[option]

    def parse(text):
        if "," in text:
            raise argparse.ArgumentTypeError(
                f"'{text}' is not a number: write decimals with a point (1.5, not 1,5)")
        if not DECIMAL.fullmatch(text):
            raise argparse.ArgumentTypeError(f"'{text}' is not a decimal number")
        v = float(text)
        if not (lo <= v <= hi):
            raise argparse.ArgumentTypeError(
                f"{v:g} {unit} is outside {lo:g} .. {hi:g} {unit} ({what})")
        return v
    return parse


def record_text(name, limit):
    """An argparse type for the record's words: printable, bounded."""
    def parse(text):
        if any(ord(c) < 0x20 or 0x7f <= ord(c) < 0xa0 for c in text):
            raise argparse.ArgumentTypeError(f"{name} holds a control character; use printable text")
        if len(text) > limit:
            raise argparse.ArgumentTypeError(f"{name} is longer than {limit} characters")
        return text
    return parse


class OneLineParser(argparse.ArgumentParser):
    """Usage errors in one line (exit 2), not the usage text again."""

    def error(self, message):
        fail(2, f"{message} (pitvol-report --help lists the options)")


def write_atomic(path, write, binary=False):
    """Writes path through a temporary file beside it, renamed into place:
    the file is complete or absent. A path that exists and is not a
    regular file (/dev/full, a FIFO) is written in place. OSError -> exit 3."""
    tmp = None
    try:
        if os.path.isdir(path):
            raise IsADirectoryError(errno.EISDIR, "it is a directory")
        if os.path.exists(path) and not os.path.isfile(path):
            with open(path, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8"})) as f:
                write(f)
            return
        fd, tmp = tempfile.mkstemp(prefix=os.path.basename(path) + ".tmp-",
                                   dir=os.path.dirname(os.path.abspath(path)))
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8"})) as f:
            write(f)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
        tmp = None
    except OSError as err:
        fail(3, f"cannot write {path}: {err.strerror or err}")
    finally:
        if tmp and os.path.exists(tmp):
            os.unlink(tmp)


def check_writable(path):
    """Before the work: the folder exists and takes a file, the path is no
    folder (so a bad --out fails at once, not after the plots)."""
    d = os.path.dirname(os.path.abspath(path))
    if os.path.isdir(path):
        fail(3, f"cannot write {path}: it is a directory")
    if not os.path.isdir(d):
        fail(3, f"cannot write {path}: the folder {d} does not exist")
    if not os.access(d, os.W_OK) and not (os.path.exists(path) and os.access(path, os.W_OK)):
        fail(3, f"cannot write {path}: the folder {d} is not writable")


def png_base64(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, metadata={"Software": None})
    return base64.b64encode(buf.getvalue()).decode("ascii")


def density(result, mass_g, moisture, max_dry=None):
    """Wet and dry density, kg/m3, and the relative compaction, %, with the
    range of the volume interval (docs/density.md): low at V + dV, high at
    V - dV (None: unbounded). As lib/density/density.c computes them."""
    v, dv = result.get("volume_cm3"), result.get("interval_cm3") or 0.0
    if mass_g is None or not v:
        return None
    def rng(f):
        hi = f / (v - dv) * 1000.0 if v - dv > 0 else None
        return f / v * 1000.0, f / (v + dv) * 1000.0, hi
    out = {"wet": rng(mass_g)}
    if moisture is not None:
        dry_mass = mass_g / (1.0 + moisture / 100.0)
        out["dry"] = rng(dry_mass)
        if max_dry:
            mid, lo, hi = out["dry"]
            out["compaction"] = (mid / max_dry * 100.0, lo / max_dry * 100.0,
                                 hi / max_dry * 100.0 if hi is not None else None)
    return out


def verdict(dens, volume, required):
    """PASS when the whole compaction range reaches the requirement, FAIL
    when none of it does, UNDECIDED when it straddles it (then also the
    volume interval under which this measurement would decide: |V - V*|,
    V* the volume at which the compaction equals the requirement), as
    pv_density_verdict() does. None without a compaction or requirement."""
    if not dens or "compaction" not in dens or not required:
        return None, None
    mid, lo, hi = dens["compaction"]
    if lo >= required:
        return "PASS", None
    if hi is not None and hi < required:
        return "FAIL", None
    return "UNDECIDED", abs(volume - volume * mid / required)


def result_block(ex, dens, mass_g, moisture):
    r = ex.result
    e = html.escape
    parts = []
    if ex.measured:
        parts.append(
            f'<p class="big" data-key="headline">{r["volume_cm3"]:.1f} ± {r["interval_cm3"]:.1f} cm³</p>')
    else:
        advice = r.get("advice") or r.get("message", "")
        parts.append(f'<div class="refused"><b>No measurement: {e(str(r.get("status")))}</b><br>'
                     f'<span data-key="advice">{e(str(advice))}</span></div>')
    parts.append('<table class="result">')
    parts.append(f'<tr><th>Method</th><td data-key="method" data-value="{e(str(r.get("method")))}">'
                 f'{e(str(r.get("method")))}</td></tr>')
    parts.append(f'<tr><th>Status</th><td data-key="status" data-value="{e(str(r.get("status")))}">'
                 f'{e(str(r.get("status")))}</td></tr>')
    for key, label, fmt, unit in RESULT_ROWS:
        v = r.get(key)
        if v is None:
            text, val = "—", "null"
        else:
            text, val = fmt.format(v) + (f" {unit}" if unit else ""), repr(v)
        parts.append(f'<tr><th>{e(row_label(r, key, label))}</th><td data-key="{key}" '
                     f'data-value="{e(val)}">{e(text)}</td></tr>')
    if r.get("gap_to_mm"):
        parts.append(f'<tr><th>Widest unseen band</th><td>{r["gap_from_mm"]:.0f} to '
                     f'{r["gap_to_mm"]:.0f} mm</td></tr>')
    parts.append("</table>")
    warnings = r.get("warnings") or []
    if warnings:
        parts.append('<p class="warn"><b>Warnings</b></p><ul class="warn">')
        parts.extend(f'<li data-key="warning">{e(w)}</li>' for w in warnings)
        parts.append("</ul>")
    else:
        parts.append('<p data-key="no-warnings">No warnings.</p>')
    notes = r.get("notes") or []
    if notes:
        parts.append('<p class="note-head">Notes</p><ul class="notes">')
        parts.extend(f'<li data-key="note">{e(n)}</li>' for n in notes)
        parts.append("</ul>")
    return "\n".join(parts)


def cell(key, value, text):
    """A data-sheet value cell: the exact value for tests, the text to read."""
    e = html.escape
    return f'<td data-key="{e(key)}" data-value="{e(value)}">{text}</td>'


def fmt_range(t, unit, digits):
    mid, lo, hi = t
    hi_t = f"{hi:.{digits}f}" if hi is not None else "?"
    return f"{mid:.{digits}f} {unit} <span class=\"range\">({lo:.{digits}f} .. {hi_t})</span>"


def data_sheet(ex, dens, rec):
    """The field density test's record, as the sand-cone data sheet has it:
    who, where, when, the inputs, the volume, the densities, the relative
    compaction with its range, and the verdict."""
    e = html.escape
    r = ex.result
    dash = "—"
    rows = []

    def row(label, key, value, text):
        rows.append(f"<tr><th>{e(label)}</th>{cell(key, value, text)}</tr>")

    def words(label, key, v):
        row(label, key, v or "", e(v) if v else f'<span class="blank">{dash}</span>')

    rows.append('<tr class="group"><th colspan="2">Test</th></tr>')
    words("Test number", "test_id", rec["test_id"])
    words("Location (station, offset, lift)", "location", rec["location"])
    words("Operator", "operator", rec["operator"])
    row("Date and time of the scan", "scan_time", rec["scan_time"], e(rec["scan_time"]))
    instrument = f'pitvol {r.get("pitvol_version", "")}, method {r.get("method", "")}'
    row("Instrument", "instrument", instrument, e(instrument))
    row("Scan file", "file", str(r.get("file", "")), f'<span class="file">{e(os.path.basename(str(r.get("file", ""))))}</span>')
    rows.append('<tr class="group"><th colspan="2">Inputs</th></tr>')
    m, w = rec["mass_g"], rec["moisture"]
    row("Wet mass of the excavated soil", "mass_g", repr(m) if m is not None else "",
        f"{m:.1f} g" if m is not None else f'<span class="blank">{dash}</span>')
    row("Moisture content (of the dry mass)", "moisture_percent", repr(w) if w is not None else "",
        f"{w:.1f} %" if w is not None else f'<span class="blank">{dash}</span>')
    md, rq = rec["max_dry"], rec["required"]
    row("Maximum dry density (Proctor)", "max_dry_density_kg_m3", repr(md) if md else "",
        f"{md:.0f} kg/m³" if md else f'<span class="blank">{dash}</span>')
    row("Required relative compaction", "required_compaction_percent", repr(rq) if rq else "",
        f"{rq:.1f} %" if rq else f'<span class="blank">{dash}</span>')
    rows.append('<tr class="group"><th colspan="2">Results</th></tr>')
    if ex.measured:
        row("Volume of the test pit", "sheet_volume_cm3", repr(r["volume_cm3"]),
            f'{r["volume_cm3"]:.1f} ± {r["interval_cm3"]:.1f} cm³')
    else:
        row("Volume of the test pit", "sheet_volume_cm3", "null", f"none: {e(str(r.get('status')))}")
    for kind, label, unit, digits in (("wet", "Wet density", "kg/m³", 0), ("dry", "Dry density", "kg/m³", 0),
                                      ("compaction", "Relative compaction", "%", 1)):
        t = (dens or {}).get(kind)
        key = {"wet": "wet_density_kg_m3", "dry": "dry_density_kg_m3",
               "compaction": "compaction_percent"}[kind]
        row(label, key, repr(t[0]) if t else "",
            fmt_range(t, unit, digits) if t else f'<span class="blank">{dash}</span>')
    v, within = verdict(dens, r.get("volume_cm3"), rq)
    if v is None:
        why = ("no volume" if not ex.measured else "needs --mass-g, --moisture-percent, "
               "--max-dry-density-kg-m3 and --required-compaction-percent")
        row("Verdict", "verdict", "", f'<span class="blank">{dash} ({e(why)})</span>')
    else:
        text = f'<b class="verdict {v.lower()}">{v}</b>'
        if v == "UNDECIDED":
            text += (f'<br><span class="decide">The compaction range straddles {rq:.1f} %: a volume '
                     f'interval under ± {within:.1f} cm³ (now ± {r["interval_cm3"]:.1f}) would '
                     f'decide. Rescan the wall that was not seen to narrow it, or dig and weigh '
                     f'the test again.</span>')
        row("Verdict", "verdict", v, text)
    sign = ('<table class="sign"><tr><td>Tested by</td><td>Checked by</td></tr>'
            '<tr class="line"><td></td><td></td></tr>'
            '<tr><td class="small">name, signature, date</td><td class="small">name, signature, '
            'date</td></tr></table>')
    return ('<table class="sheet">' + "\n".join(rows) + "</table>" + sign)


def render_html(ex, figs, dens, mass_g, moisture, rec):
    e = html.escape
    r = ex.result
    body = ['<h1>Field density test: data sheet</h1>',
            '<p class="sub">In-place density by scanned test pit volume (pitvol); the '
            'volume interval carried into every density</p>',
            '<section id="sheet">', data_sheet(ex, dens, rec), "</section>",
            '<h2>Measurement</h2>',
            f'<p class="file">{e(str(r.get("file", "")))} &middot; pitvol '
            f'{e(str(r.get("pitvol_version", "")))} &middot; units {e(str(r.get("units", "")))}</p>',
            '<section id="result">', result_block(ex, dens, mass_g, moisture), "</section>"]
    for fid, title, fig in figs:
        body.append(f'<figure id="{fid}"><h2>{e(title)}</h2>')
        if fig is None:
            why = ("the per-layer methods have no wall grid" if fid in ("outline",)
                   else "the scan could not be levelled" if fid == "side" else "no data")
            body.append(f'<p class="note">Not available: {why}.</p>')
        else:
            body.append(f'<img alt="{e(title)}" src="data:image/png;base64,{png_base64(fig)}">')
        body.append(f"<figcaption>{e(CAPTIONS[fid])}</figcaption></figure>")
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>pitvol report: {e(os.path.basename(str(r.get('file', ''))))}</title>"
            f"<style>{CSS}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")


def write_pdf(path, ex, figs, dens, rec):
    """Page 1 the data sheet (and the measurement's lines), then a page per
    figure. Long lines wrap at the page's width."""
    from matplotlib.backends.backend_pdf import PdfPages
    import matplotlib.pyplot as plt
    import textwrap
    r = ex.result

    def rng(t, digits):
        if not t:
            return "-"
        mid, lo, hi = t
        return f"{mid:.{digits}f} ({lo:.{digits}f} .. {'?' if hi is None else f'{hi:.{digits}f}'})"
    def opt(x, f):
        return "-" if x is None else f.format(x)
    v, within = verdict(dens, r.get("volume_cm3"), rec["required"])
    lines = ["FIELD DENSITY TEST: DATA SHEET", "",
             f"Test number:            {rec['test_id'] or '-'}",
             f"Location:               {rec['location'] or '-'}",
             f"Operator:               {rec['operator'] or '-'}",
             f"Date and time of scan:  {rec['scan_time']}",
             f"Instrument:             pitvol {r.get('pitvol_version', '')}, method {r.get('method', '')}",
             f"Scan file:              {os.path.basename(str(r.get('file', '')))}", "",
             "Wet mass:               " + opt(rec["mass_g"], "{:.1f} g"),
             "Moisture content:       " + opt(rec["moisture"], "{:.1f} %"),
             "Max dry density:        " + opt(rec["max_dry"], "{:.0f} kg/m3"),
             "Required compaction:    " + opt(rec["required"], "{:.1f} %"),
             ""]
    if ex.measured:
        lines.append(f"Volume:                 {r['volume_cm3']:.1f} +/- {r['interval_cm3']:.1f} cm3")
    else:
        lines.append(f"Volume:                 none ({r.get('status')})")
        lines += textwrap.wrap(str(r.get("advice") or r.get("message", "")), 84)
    lines += [f"Wet density:            {rng((dens or {}).get('wet'), 0)} kg/m3",
              f"Dry density:            {rng((dens or {}).get('dry'), 0)} kg/m3",
              f"Relative compaction:    {rng((dens or {}).get('compaction'), 1)} %",
              f"Verdict:                {v or '-'}"]
    if v == "UNDECIDED":
        lines += textwrap.wrap(f"A volume interval under +/- {within:.1f} cm3 (now +/- "
                               f"{r['interval_cm3']:.1f}) would decide: rescan the unseen wall, "
                               "or dig and weigh the test again.", 84)
    lines += ["", "Measurement:"]
    for key, label, fmt, unit in RESULT_ROWS:
        val = r.get(key)
        lines.append(f"  {row_label(r, key, label)}:  " + ("-" if val is None else fmt.format(val) + f" {unit}"))
    for w in r.get("warnings") or []:
        lines += textwrap.wrap(f"Warning: {w}", 84, subsequent_indent="  ")
    for n in r.get("notes") or []:
        lines += textwrap.wrap(f"Note: {n}", 84, subsequent_indent="  ")
    lines += ["", "", "Tested by: ______________________    Checked by: ______________________"]
    with PdfPages(path, metadata={"Creator": "pitvol-report", "CreationDate": None}) as pdf:
        page = plt.figure(figsize=(8.27, 11.69))  # A4
        page.text(0.07, 0.96, "\n".join(lines), va="top", family="monospace", fontsize=9)
        pdf.savefig(page)
        plt.close(page)
        for _, _, fig in figs:
            if fig is not None:
                pdf.savefig(fig)


def scan_time(ex, source):
    """When the scan was made, as the files know it: the scan file's
    modification time (the scanner writes it once), else the clock."""
    for path in (str(ex.result.get("file", "")), source):
        if path and os.path.isfile(path):
            t = os.path.getmtime(path)
            break
    else:
        t = time.time()
    return time.strftime("%Y-%m-%d %H:%M", time.localtime(t))


def find_pitvol(explicit):
    if explicit:
        return explicit
    for cand in (os.path.join(HERE, "pitvol"), shutil.which("pitvol")):
        if cand and os.access(cand, os.X_OK):
            return cand
    fail(2, "cannot find the pitvol program: pass --pitvol PATH (build/bin/pitvol)")


def main(argv):
    ap = OneLineParser(prog="pitvol-report", description=__doc__.split("\n\n")[0])
    ap.add_argument("source", help="a scan file, or a directory written by pitvol measure --export")
    ap.add_argument("--out", required=True, help="the HTML page to write")
    ap.add_argument("--pdf", help="also a printable PDF")
    ap.add_argument("--pitvol", help="the pitvol program (default: beside this tool, else PATH)")
    ap.add_argument("--mass-g", type=typed_number("mass-g"),
                    help="wet mass of the excavated soil, g (50 .. 100000): density")
    ap.add_argument("--moisture-percent", type=typed_number("moisture-percent"),
                    help="water content, %% of the dry mass (0 .. 100)")
    ap.add_argument("--max-dry-density-kg-m3", type=typed_number("max-dry-density-kg-m3"),
                    help="the material's Proctor maximum dry density, kg/m3 (1000 .. 2800): "
                         "relative compaction")
    ap.add_argument("--required-compaction-percent", type=typed_number("required-compaction-percent"),
                    help="the relative compaction the specification requires, %% (50 .. 110): "
                         "the verdict PASS, FAIL or UNDECIDED")
    ap.add_argument("--test-id", type=record_text("--test-id", 40), default="",
                    help="the test number on the data sheet")
    ap.add_argument("--location", type=record_text("--location", 80), default="",
                    help="where the test was dug: station, offset, lift")
    ap.add_argument("--operator", type=record_text("--operator", 60), default="",
                    help="who ran the test")
    ap.add_argument("--scan-time", type=record_text("--scan-time", 40),
                    help="date and time of the scan on the data sheet (default: the scan "
                         "file's modification time, local time; else the clock)")
    ap.epilog = "options after -- go to pitvol measure (e.g. -- --units m --method paper)"
    # Split at "--" here: argparse would take the first option after it as
    # the source's neighbour and refuse it.
    measure_args = []
    if "--" in argv:
        cut = argv.index("--")
        argv, measure_args = argv[:cut], argv[cut + 1:]
    a = ap.parse_args(argv)
    a.measure_args = measure_args
    check_writable(a.out)
    if a.pdf:
        check_writable(a.pdf)

    tmp = None
    try:
        if os.path.isdir(a.source):
            export_dir = a.source
        elif os.path.exists(a.source):
            tmp = tempfile.mkdtemp(prefix="pitvol-report-")
            export_dir = tmp
            cmd = [find_pitvol(a.pitvol), "measure", a.source, "--export", tmp, "--no-progress",
                   *a.measure_args]
            p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            # 0 measured, 4 refused (the export still says why): both make a page.
            if p.returncode not in (0, 4):
                sys.stderr.write(p.stderr)
                fail(3 if p.returncode in (2, 3) else 5,
                     f"`{' '.join(cmd)}` failed with exit code {p.returncode}")
        else:
            fail(3, f"{a.source}: no such file or directory")
        try:
            ex = report_data.Export(export_dir)
        except report_data.ExportError as err:
            fail(3, str(err))
        dens = (density(ex.result, a.mass_g, a.moisture_percent, a.max_dry_density_kg_m3)
                if ex.measured else None)
        rec = {"test_id": a.test_id, "location": a.location, "operator": a.operator,
               "scan_time": a.scan_time or scan_time(ex, a.source), "mass_g": a.mass_g,
               "moisture": a.moisture_percent, "max_dry": a.max_dry_density_kg_m3,
               "required": a.required_compaction_percent}
        figs = report_plots.all_figures(ex)
        page = render_html(ex, figs, dens, a.mass_g, a.moisture_percent, rec)
        write_atomic(a.out, lambda f: f.write(page))
        if a.pdf:
            write_atomic(a.pdf, lambda f: write_pdf(f, ex, figs, dens, rec), binary=True)
        report_plots.close(figs)
    finally:
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)
    print(f"pitvol-report: wrote {a.out}" + (f" and {a.pdf}" if a.pdf else ""))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except KeyboardInterrupt:
        fail(130, "interrupted")
    except Exception as err:  # noqa: BLE001  one line, not a traceback
        fail(5, f"internal error: {type(err).__name__}: {err}; please report it with the scan")
