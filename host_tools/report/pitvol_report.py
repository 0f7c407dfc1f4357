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

CSS = """
body { font-family: sans-serif; margin: 2em auto; max-width: 1100px; color: #212121; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
.file { color: #616161; font-family: monospace; }
table.result { border-collapse: collapse; margin: 1em 0; }
table.result td, table.result th { border-bottom: 1px solid #e0e0e0; padding: 4px 12px; text-align: left; }
.big { font-size: 1.6em; font-weight: bold; }
.refused { background: #ffebee; border: 1px solid #c62828; padding: 0.8em; }
.warn { color: #e65100; }
figure { margin: 1.5em 0; }
figure img { max-width: 100%; border: 1px solid #eeeeee; }
figcaption { color: #424242; font-size: 0.9em; }
.note { color: #757575; font-style: italic; }
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
    "side": "The levelled cloud seen from the side (x and y through the axis): the floor plane "
            "at z = 0, the rim the volume stops at, and the fitted wall in that plane.",
}


def fail(code, msg):
    print(f"pitvol-report: {msg}", file=sys.stderr)
    sys.exit(code)


# Plausible ranges of the numbers a user types: the numbers of
# firmware/density/include/pitvol/density.h (tests/report checks they agree),
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


def density(result, mass_g, moisture):
    """Wet and dry density, kg/m3, with the range of the volume interval
    (docs/density.md): low at V + dV, high at V - dV (None: unbounded)."""
    v, dv = result.get("volume_cm3"), result.get("interval_cm3") or 0.0
    if mass_g is None or not v:
        return None
    def rng(f):
        hi = f / (v - dv) * 1000.0 if v - dv > 0 else None
        return f / v * 1000.0, f / (v + dv) * 1000.0, hi
    out = {"wet": rng(mass_g)}
    if moisture is not None:
        out["dry"] = rng(mass_g / (1.0 + moisture / 100.0))
    return out


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
    if dens:
        for kind, label in (("wet", "Wet density"), ("dry", "Dry density")):
            if kind not in dens:
                continue
            mid, lo, hi = dens[kind]
            hi_t = f"{hi:.0f}" if hi is not None else "?"
            parts.append(f'<tr><th>{label}</th><td data-key="{kind}_density_kg_m3" '
                         f'data-value="{mid!r}">{mid:.0f} kg/m³ ({lo:.0f} .. {hi_t})</td></tr>')
        src = f"{mass_g:g} g" + (f", moisture {moisture:g} %" if moisture is not None else "")
        parts.append(f"<tr><th>Density from</th><td>{e(src)}</td></tr>")
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


def render_html(ex, figs, dens, mass_g, moisture):
    e = html.escape
    r = ex.result
    body = [f"<h1>Test pit scan report</h1>",
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


def write_pdf(path, ex, figs, dens):
    from matplotlib.backends.backend_pdf import PdfPages
    import matplotlib.pyplot as plt
    r = ex.result
    with PdfPages(path, metadata={"Creator": "pitvol-report", "CreationDate": None}) as pdf:
        page = plt.figure(figsize=(8.27, 11.69))  # A4
        lines = ["Test pit scan report", str(r.get("file", "")), ""]
        if ex.measured:
            lines.append(f"Volume  {r['volume_cm3']:.1f} +/- {r['interval_cm3']:.1f} cm3")
        else:
            lines.append(f"No measurement: {r.get('status')}")
            lines.append(str(r.get("advice") or r.get("message", "")))
        for key, label, fmt, unit in RESULT_ROWS:
            v = r.get(key)
            lines.append(f"{row_label(r, key, label)}:  " +
                         ("-" if v is None else fmt.format(v) + f" {unit}"))
        lines.append(f"Method:  {r.get('method')}")
        if dens:
            for kind in ("wet", "dry"):
                if kind in dens:
                    lines.append(f"{kind.capitalize()} density:  {dens[kind][0]:.0f} kg/m3")
        for w in r.get("warnings") or []:
            lines.append(f"Warning: {w}")
        for n in r.get("notes") or []:
            lines.append(f"Note: {n}")
        page.text(0.08, 0.95, "\n".join(lines), va="top", family="monospace", fontsize=10)
        pdf.savefig(page)
        plt.close(page)
        for _, _, fig in figs:
            if fig is not None:
                pdf.savefig(fig)


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
        dens = density(ex.result, a.mass_g, a.moisture_percent) if ex.measured else None
        figs = report_plots.all_figures(ex)
        page = render_html(ex, figs, dens, a.mass_g, a.moisture_percent)
        write_atomic(a.out, lambda f: f.write(page))
        if a.pdf:
            write_atomic(a.pdf, lambda f: write_pdf(f, ex, figs, dens), binary=True)
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
