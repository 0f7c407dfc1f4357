#!/usr/bin/python3
"""The scan report (label report, docs/report.md), one CTest test per step:

  make BIN WORK       fixture: a corpus scan (pitvol-sim, family necking),
                      pitvol measure --json, pitvol-report --pdf, two exports,
                      the page again from an export
  page WORK           the HTML parses, every image is a non-blank PNG, the
                      result block equals the JSON, the PDF, the export
                      (bounded, deterministic), the same page bit for bit
  chromium WORK       headless Chromium renders the page: non-blank screenshot
                      (exit 77 = skipped, with the reason, if it is missing)
  methods BIN WORK    method paper and a refused scan (not a pit) make pages
  accuracy BIN WORK   pitvol-accuracy --html on a two-scan corpus: the page,
                      its images, the results CSV
"""
import base64
import csv
import html.parser
import io
import json
import math
import os
import re
import shutil
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402  (PNG decoding: Debian python3-matplotlib)
import numpy as np  # noqa: E402

SKIP = 77  # CTest SKIP_RETURN_CODE
MASS_G, MOISTURE, MAX_DRY = 21000.0, 11.8, 1850.0
FIGURES = ["pit3d", "area", "outline", "coverage", "side"]
RECORD = ["--test-id", "FDT-0142", "--location", "STA 1+250, 2.5 m LT, lift 3", "--operator",
          "J. Okafor", "--max-dry-density-kg-m3", str(MAX_DRY)]
NUMBERS = ["volume_cm3", "interval_cm3", "depth_mm", "tilt_deg", "unseen_share", "layers_used",
           "layers_rejected", "points_in", "points_used"]
EXPORT_FILES = ["model.json", "points.csv", "layers.csv", "coverage.csv", "wall_grid.csv",
                "outline.csv"]


def fail(msg):
    print(f"FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)


def run(cmd, codes=(0,), **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode not in codes:
        fail(f"{' '.join(cmd)} exited {p.returncode}:\n{p.stdout}\n{p.stderr}")
    return p


class Page(html.parser.HTMLParser):
    """The page's images, figures and data-key cells; tags must balance."""
    VOID = {"meta", "img", "br", "link", "hr", "input"}

    def __init__(self):
        super().__init__()
        self.images, self.figures, self.values, self.stack = [], [], {}, []
        self.text_of, self._key, self.errors = {}, None, []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag not in self.VOID:
            self.stack.append(tag)
        if tag == "img":
            self.images.append(a.get("src", ""))
        if tag == "figure":
            self.figures.append(a.get("id"))
        if "data-key" in a and "data-value" in a:
            self.values[a["data-key"]] = a["data-value"]
            self._key = a["data-key"]
            self.text_of[self._key] = ""

    def handle_endtag(self, tag):
        if tag in self.VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else None}>")
            return
        self.stack.pop()
        if tag == "td":
            self._key = None

    def handle_data(self, data):
        if self._key:
            self.text_of[self._key] += data


def parse_page(path):
    p = Page()
    with open(path, encoding="utf-8") as f:
        p.feed(f.read())
    p.close()
    check(not p.errors, f"{path}: unbalanced tags: {p.errors[:3]}")
    check(p.stack == [], f"{path}: unclosed tags {p.stack}")
    return p


def check_png(data, what, min_w=300, min_h=150):
    """A PNG that decodes, is large enough and is not one flat colour."""
    check(data[:8] == b"\x89PNG\r\n\x1a\n", f"{what}: not a PNG")
    img = matplotlib.image.imread(io.BytesIO(data), format="png")
    h, w = img.shape[:2]
    check(w >= min_w and h >= min_h, f"{what}: {w}x{h} px, too small")
    rgb = img[..., :3].reshape(-1, 3)
    bg = np.median(rgb, axis=0)
    drawn = np.mean(np.abs(rgb - bg).sum(axis=1) > 0.1)
    check(drawn > 0.005, f"{what}: blank ({drawn:.2%} of the pixels differ from the background)")
    return w, h, drawn


def cmd_make(bin_dir, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    # A corpus scan (the simulator's necking family): its neck hides wall,
    # so the page has unseen bands to show.
    run([os.path.join(bin_dir, "pitvol-sim"), "scan", "--family", "necking", "--seed", "4",
         "--out", os.path.join(work, "scan")])
    scan = os.path.join(work, "scan.ply")
    p = run([os.path.join(bin_dir, "pitvol"), "measure", scan, "--json"])
    with open(os.path.join(work, "measure.json"), "w") as f:
        f.write(p.stdout)
    run([os.path.join(bin_dir, "pitvol-report"), scan, "--out", os.path.join(work, "page.html"),
         "--pdf", os.path.join(work, "page.pdf"), "--mass-g", str(MASS_G),
         "--moisture-percent", str(MOISTURE), *RECORD, "--required-compaction-percent", "100"])
    for d in ("export1", "export2"):
        run([os.path.join(bin_dir, "pitvol"), "measure", scan, "--export", os.path.join(work, d)])
    # The same page again, from the export directory instead of the scan.
    run([os.path.join(bin_dir, "pitvol-report"), os.path.join(work, "export1"), "--out",
         os.path.join(work, "page_from_export.html"), "--mass-g", str(MASS_G),
         "--moisture-percent", str(MOISTURE), *RECORD, "--required-compaction-percent", "100"])
    print("report fixture made in", work)


def cmd_page(work):
    with open(os.path.join(work, "measure.json")) as f:
        truth = json.load(f)
    check(truth["status"] == "PV_OK", f"the scan did not measure: {truth['status']}")
    page = parse_page(os.path.join(work, "page.html"))
    check(page.figures == FIGURES, f"figures {page.figures}, expected {FIGURES}")
    check(len(page.images) == len(FIGURES), f"{len(page.images)} images, expected {len(FIGURES)}")
    for fid, src in zip(FIGURES, page.images):
        prefix = "data:image/png;base64,"
        check(src.startswith(prefix), f"{fid}: image not embedded as a PNG data URL")
        w, h, drawn = check_png(base64.b64decode(src[len(prefix):], validate=True), fid)
        print(f"image {fid}: {w}x{h} px, {drawn:.1%} drawn")
    # The result block: the exact JSON values, and the text shows them rounded.
    for key in NUMBERS:
        check(key in page.values, f"result block lacks {key}")
        v = float(page.values[key])
        check(v == truth[key], f"{key}: page {page.values[key]}, pitvol measure --json {truth[key]}")
    check(page.values["method"] == truth["method"], "method differs")
    check(page.values["status"] == truth["status"], "status differs")
    vol = truth["volume_cm3"]
    check(f"{vol:.1f}" in page.text_of["volume_cm3"], f"volume text {page.text_of['volume_cm3']!r}")
    check(f"{truth['interval_cm3']:.1f}" in page.text_of["interval_cm3"], "interval text")
    wet = MASS_G / vol * 1000.0
    check(math.isclose(float(page.values["wet_density_kg_m3"]), wet, rel_tol=1e-12), "wet density")
    dry = wet / (1 + MOISTURE / 100.0)
    check(math.isclose(float(page.values["dry_density_kg_m3"]), dry, rel_tol=1e-12), "dry density")
    # The data sheet: the record as typed, the compaction and its range
    # from the volume interval, the verdict (100 % lies inside the range:
    # UNDECIDED, with the interval that would decide).
    for key, want in (("test_id", "FDT-0142"), ("location", "STA 1+250, 2.5 m LT, lift 3"),
                      ("operator", "J. Okafor"), ("mass_g", repr(MASS_G)),
                      ("max_dry_density_kg_m3", repr(MAX_DRY)),
                      ("required_compaction_percent", "100.0")):
        check(page.values.get(key) == want, f"data sheet {key}: {page.values.get(key)!r}, want {want!r}")
    rc = dry / MAX_DRY * 100.0
    check(math.isclose(float(page.values["compaction_percent"]), rc, rel_tol=1e-12), "compaction")
    lo = MASS_G / (vol + truth["interval_cm3"]) * 1000 / (1 + MOISTURE / 100) / MAX_DRY * 100
    hi = MASS_G / (vol - truth["interval_cm3"]) * 1000 / (1 + MOISTURE / 100) / MAX_DRY * 100
    check(f"({lo:.1f} .. {hi:.1f})" in page.text_of["compaction_percent"],
          f"compaction range {page.text_of['compaction_percent']!r}, want {lo:.1f} .. {hi:.1f}")
    want_verdict = "PASS" if lo >= 100 else "FAIL" if hi < 100 else "UNDECIDED"
    check(page.values["verdict"] == want_verdict, f"verdict {page.values['verdict']}, want {want_verdict}")
    if want_verdict == "UNDECIDED":
        within = abs(vol - vol * rc / 100.0)
        check(f"under ± {within:.1f} cm³" in page.text_of["verdict"], f"decide: {page.text_of['verdict']!r}")
    # The PDF: one page for the data sheet and one per figure.
    with open(os.path.join(work, "page.pdf"), "rb") as f:
        pdf = f.read()
    check(pdf.startswith(b"%PDF-"), "page.pdf is not a PDF")
    pages = pdf.count(b"/Type /Page") - pdf.count(b"/Type /Pages")
    check(pages == 1 + len(FIGURES), f"page.pdf has {pages} pages, expected {1 + len(FIGURES)}")
    # The export: bounded, deterministic, the same result as --json.
    e1, e2 = os.path.join(work, "export1"), os.path.join(work, "export2")
    for name in EXPORT_FILES:
        with open(os.path.join(e1, name), "rb") as a, open(os.path.join(e2, name), "rb") as b:
            check(a.read() == b.read(), f"export {name} differs between two runs")
    with open(os.path.join(e1, "model.json")) as f:
        model = json.load(f)
    with open(os.path.join(e1, "points.csv")) as f:
        rows = sum(1 for _ in f) - 1
    check(rows == model["points_written"] and 0 < rows <= 50000, f"points.csv has {rows} rows")
    check(model["points_stride"] == math.ceil(model["points_exportable"] / 50000), "stride")
    with open(os.path.join(e1, "result.json")) as f:
        exported = json.load(f)
    for key in NUMBERS + ["coverage", "status", "warnings"]:
        check(exported[key] == truth[key], f"result.json {key} differs from --json")
    g = model["wall_grid"]
    with open(os.path.join(e1, "wall_grid.csv")) as f:
        check(sum(1 for _ in f) - 1 == g["theta_bins"] * g["z_bins"], "wall_grid.csv rows")
    # Same input, same bits: the page from the scan and from its export.
    with open(os.path.join(work, "page.html"), "rb") as a, \
            open(os.path.join(work, "page_from_export.html"), "rb") as b:
        check(a.read() == b.read(), "the page from the export differs from the page from the scan")
    print(f"page: {len(page.images)} images, {len(NUMBERS)} numbers equal, pdf {pages} pages")


def cmd_chromium(work):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        print("SKIPPED: chromium is not installed: run toolchain/install-deps.sh --browser")
        return SKIP
    shot = os.path.join(work, "screenshot.png")
    if os.path.exists(shot):
        os.remove(shot)
    page = "file://" + os.path.abspath(os.path.join(work, "page.html"))
    profile = os.path.join(work, "chromium-profile")
    run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
         f"--user-data-dir={profile}", f"--screenshot={shot}", "--window-size=1200,3000", page],
        timeout=120)
    check(os.path.exists(shot), "chromium wrote no screenshot")
    with open(shot, "rb") as f:
        w, h, drawn = check_png(f.read(), "screenshot", 1200, 3000)
    # The images render: the lower part of the page (the figures) is drawn too.
    img = matplotlib.image.imread(shot)[..., :3]
    lower = img[h // 3:]
    check(np.mean(np.abs(lower - 1.0).sum(axis=2) > 0.1) > 0.02, "the figures did not render")
    print(f"chromium screenshot {w}x{h}, {drawn:.1%} drawn")
    return 0


def cmd_methods(bin_dir, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    scan = os.path.join(work, "pit.ply")
    run([os.path.join(bin_dir, "pitvol-synth"), scan, "--points", "120000", "--seed", "3"])
    report = os.path.join(bin_dir, "pitvol-report")
    # Method paper: no wall grid, so no outline; the other figures are there.
    out = os.path.join(work, "paper.html")
    run([report, scan, "--out", out, "--", "--method", "paper"])
    p = parse_page(out)
    check(p.values["method"] == "paper", "the page's method is not paper")
    check(len(p.images) == len(FIGURES) - 1, f"paper page: {len(p.images)} images")
    with open(out, encoding="utf-8") as f:
        check("Not available: the per-layer methods have no wall grid" in f.read(), "no note")
    # A flat patch of ground is not a pit: a page that says so, no volume.
    flat = os.path.join(work, "flat.xyz")
    with open(flat, "w") as f:
        for i in range(200):
            for j in range(200):
                f.write(f"{i * 2.0} {j * 2.0} {0.01 * ((i * 7 + j * 13) % 5)}\n")
    run([os.path.join(bin_dir, "pitvol"), "measure", flat], codes=(4,))
    out = os.path.join(work, "flat.html")
    run([report, flat, "--out", out])
    p = parse_page(out)
    check(p.values["status"] != "PV_OK" and p.values["volume_cm3"] == "null", "a flat scan got a volume")
    with open(out, encoding="utf-8") as f:
        check("No measurement" in f.read(), "the refusal is not on the page")
    # --export onto a file: refused before the measurement, with the reason.
    p = run([os.path.join(bin_dir, "pitvol"), "measure", scan, "--export", scan], codes=(3,))
    check("is not a directory" in p.stderr and p.stdout == "", f"--export onto a file: {p.stderr}")
    # Usage and input errors: exit codes, not a page.
    check(run([report, os.path.join(work, "missing.ply"), "--out", out], codes=(3,)).returncode == 3,
          "missing file")
    print("paper and refused pages made")


def cmd_inputs(bin_dir, page_work, work):
    """The data sheet's verdict at both ends; every typed number refused
    outside its plausible range (the ranges of density.h) in one line with
    exit 2; an unwritable --out or --pdf refused in one line with exit 3
    before the work, nothing half-written, no traceback."""
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    report = os.path.join(bin_dir, "pitvol-report")
    export = os.path.join(page_work, "export1")
    base = [report, export, "--mass-g", str(MASS_G), "--moisture-percent", str(MOISTURE),
            "--max-dry-density-kg-m3", str(MAX_DRY)]
    for required, want in (("90", "PASS"), ("108", "FAIL")):
        out = os.path.join(work, f"v{required}.html")
        run(base + ["--required-compaction-percent", required, "--out", out])
        check(parse_page(out).values["verdict"] == want, f"required {required}: not {want}")
    # The report's ranges are the board's (lib/density/include/pitvol/density.h).
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "host_tools", "report"))
    import pitvol_report  # noqa: E402
    header = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "lib",
                          "density", "include", "pitvol", "density.h")
    with open(header) as f:
        defs = dict(re.findall(r"#define (PV_DENSITY_\w+) ([0-9.]+)", f.read()))
    for opt, lo, hi in (("mass-g", "MIN_MASS_G", "MAX_MASS_G"),
                        ("moisture-percent", None, "MAX_MOISTURE_PERCENT"),
                        ("max-dry-density-kg-m3", "MIN_REFERENCE_KG_M3", "MAX_REFERENCE_KG_M3"),
                        ("required-compaction-percent", "MIN_REQUIRED_PERCENT", "MAX_REQUIRED_PERCENT")):
        rlo, rhi = pitvol_report.RANGES[opt][:2]
        check(rlo == (float(defs["PV_DENSITY_" + lo]) if lo else 0.0) and rhi == float(defs["PV_DENSITY_" + hi]),
              f"--{opt}: the report's range {rlo} .. {rhi} is not density.h's")
    out = os.path.join(work, "x.html")
    for args in (["--mass-g", "1e308"], ["--mass-g", "1e-300"], ["--mass-g", "0x10"],
                 ["--moisture-percent", "1e308"], ["--moisture-percent", "12,5"],
                 ["--max-dry-density-kg-m3", "1.85"], ["--required-compaction-percent", "inf"],
                 ["--test-id", "T\x1b[2J"], ["--bogus"]):
        p = run([report, export, "--out", out, *args], codes=(2,))
        check(p.stderr.count("\n") == 1 and "Traceback" not in p.stderr, f"{args}: {p.stderr}")
    p = run([report, export, "--out", out, "--mass-g", "1e308"], codes=(2,))
    check("outside 50 .. 100000 g" in p.stderr, f"the range is not named: {p.stderr}")
    for target in (os.path.join(work, "no", "x.html"), work, "/dev/full"):
        if target == "/dev/full" and not os.path.exists(target):
            continue
        p = run([report, export, "--out", target], codes=(3,))
        check(p.stderr.count("\n") == 1 and "Traceback" not in p.stderr, f"--out {target}: {p.stderr}")
    p = run([report, export, "--out", out, "--pdf", os.path.join(work, "no", "x.pdf")], codes=(3,))
    check(not os.path.exists(out), "--out written although --pdf could not be")
    left = [n for n in os.listdir(work) if ".tmp-" in n]
    check(not left, f"half-written files left: {left}")
    print("inputs: PASS and FAIL, 9 refusals in one line, unwritable outputs refused")


def cmd_accuracy(bin_dir, page_work, work):
    """A two-case corpus (the fixture's necking scan and a cylinder), both
    methods: the page has the summary and three non-blank plots."""
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    run([os.path.join(bin_dir, "pitvol-sim"), "scan", "--family", "cylinder", "--seed", "2",
         "--points", "150000", "--out", os.path.join(work, "cyl")])
    shutil.copy(os.path.join(page_work, "scan.ply"), os.path.join(work, "neck.ply"))
    exact = {}
    for name, src in (("cyl", os.path.join(work, "cyl.json")),
                      ("neck", os.path.join(page_work, "scan.json"))):
        with open(src) as f:
            exact[name] = json.load(f)["exact_volume_cm3"]
    with open(os.path.join(work, "manifest.csv"), "w") as f:
        f.write("case,family,ground,seed,noise_mm,points,tilt_deg,exact_volume_cm3,set,stress\n")
        f.write(f"cyl,cylinder,1,2,0.02,150000,0,{exact['cyl']:.6f},test,none\n")
        f.write(f"neck,necking,1,4,0.02,300000,0,{exact['neck']:.6f},test,none\n")
    out = os.path.join(work, "accuracy.html")
    run([os.path.join(bin_dir, "pitvol-accuracy"), work, "--method", "surface", "--method", "paper",
         "--html", out])
    with open(os.path.join(work, "accuracy-results.csv")) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) == 4, f"{len(rows)} result rows, expected 2 cases x 2 methods")
    for r in rows:
        if r["status"] == "PV_OK":
            err = (float(r["volume_cm3"]) - float(r["exact_cm3"])) / float(r["exact_cm3"]) * 100
            check(math.isclose(err, float(r["error_pct"]), abs_tol=1e-4), f"error of {r['case']}")
    p = parse_page(out)
    check(p.figures == ["error", "mean", "interval"], f"accuracy figures {p.figures}")
    for fid, src in zip(p.figures, p.images):
        check_png(base64.b64decode(src.split(",", 1)[1]), f"accuracy {fid}")
    with open(out, encoding="utf-8") as f:
        text = f.read()
    for m in ("surface", "paper"):
        check(f'data-method="{m}"' in text, f"summary lacks {m}")
    print("accuracy page: 3 images, 4 results")


def main(argv):
    if len(argv) == 3 and argv[0] == "make":
        return cmd_make(argv[1], argv[2]) or 0
    if len(argv) == 2 and argv[0] == "page":
        return cmd_page(argv[1]) or 0
    if len(argv) == 2 and argv[0] == "chromium":
        return cmd_chromium(argv[1])
    if len(argv) == 3 and argv[0] == "methods":
        return cmd_methods(argv[1], argv[2]) or 0
    if len(argv) == 4 and argv[0] == "inputs":
        return cmd_inputs(argv[1], argv[2], argv[3]) or 0
    if len(argv) == 4 and argv[0] == "accuracy":
        return cmd_accuracy(argv[1], argv[2], argv[3]) or 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
