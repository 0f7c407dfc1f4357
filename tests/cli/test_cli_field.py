#!/usr/bin/python3
"""What a technician reads from pitvol measure (label cli): warnings from
the core's one table and none on an ordinary scan, labels that say what
they count, advice that follows from the failing check, one-line errors
with exit 2 or 3 and no half-written output.

  test_cli_field.py BIN WORK
"""
import json
import os
import shutil
import subprocess
import sys

BIN, WORK = sys.argv[1], sys.argv[2]
THINNED = "dense parts of the scan were thinned to fit the fixed memory"
BRIDGED = "part of the wall was not seen and was bridged from the wall around it"


def fail(msg):
    print(f"FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)


def run(*args, codes=(0,)):
    p = subprocess.run([os.path.join(BIN, args[0]), *args[1:]], capture_output=True, text=True,
                       stdin=subprocess.DEVNULL)
    if p.returncode not in codes:
        fail(f"{' '.join(args)} exited {p.returncode}, want {codes}:\n{p.stdout}\n{p.stderr}")
    return p


def one_line(p, what):
    check(p.stderr.count("\n") == 1, f"{what}: want one line on stderr, got:\n{p.stderr}")


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    pit = os.path.join(WORK, "pit.ply")
    run("pitvol-synth", pit, "--points", "120000", "--seed", "3")
    neck = os.path.join(WORK, "neck")
    run("pitvol-sim", "scan", "--family", "necking", "--seed", "4", "--out", neck)

    # 1. An ordinary scan: no warning line; thinning is a note in the JSON.
    p = run("pitvol", "measure", pit)
    check("warning" not in p.stdout, f"an ordinary scan printed a warning:\n{p.stdout}")
    j = json.loads(run("pitvol", "measure", pit, "--json").stdout)
    check(j["warnings"] == [], f"ordinary scan: warnings {j['warnings']}")
    check(any(n.startswith(THINNED) for n in j["notes"]), f"ordinary scan: notes {j['notes']}")
    check(j["warning_bits"] & 1, "warning_bits lacks the thinning bit")
    # The necking scan rests 5 % of its volume on unseen wall: the CLI says so.
    p = run("pitvol", "measure", neck + ".ply")
    check(f"warning        {BRIDGED}" in p.stdout, f"necking scan: no bridged warning:\n{p.stdout}")
    j = json.loads(run("pitvol", "measure", neck + ".ply", "--json").stdout)
    check(j["unseen_share"] > 0.01 and any(w.startswith(BRIDGED) for w in j["warnings"]),
          f"necking scan JSON: {j['warnings']}")
    print("warnings: none on an ordinary scan, the bridge on the necking scan")

    # 2. Labels per method, and the layers CSV's columns.
    p = run("pitvol", "measure", pit)
    check("wall bins      " in p.stdout and "layers" not in p.stdout, f"surface labels:\n{p.stdout}")
    p = run("pitvol", "measure", pit, "--method", "paper")
    check("layers         " in p.stdout and "wall bins" not in p.stdout, f"paper labels:\n{p.stdout}")
    for method, header in (("surface", "z_mm,area_mm2,kept,unseen_share,bridged"),
                           ("paper", "z_mm,area_mm2,points,kept,shape,bridged")):
        out = os.path.join(WORK, f"layers-{method}.csv")
        run("pitvol", "measure", pit, "--method", method, "--layers", out)
        with open(out) as f:
            rows = f.read().splitlines()
        check(rows[0] == header, f"--layers {method}: header {rows[0]}")
        if method == "paper":
            pts = [int(r.split(",")[2]) for r in rows[1:]]
            check(sum(1 for v in pts if v > 0) > len(pts) // 2, "paper: the points column is empty")
    print("labels: wall bins for surface, layers for paper; the layers CSV per method")

    # 3. Advice from the failing check: 5,837 points are too few points, not
    # an unseen band to tilt into.
    few = os.path.join(WORK, "few")
    run("pitvol-sim", "scan", "--family", "cylinder", "--seed", "3", "--points", "5837", "--out", few)
    p = run("pitvol", "measure", few + ".ply", codes=(4,))
    check("too few points (5837)" in p.stderr and "tilt" not in p.stderr, f"5,837 points:\n{p.stderr}")
    j = json.loads(run("pitvol", "measure", few + ".ply", "--json", codes=(4,)).stdout)
    check("too few points" in j["advice"], f"advice {j.get('advice')}")
    up = os.path.join(WORK, "upside.ply")
    run("pitvol-synth", up, "--points", "120000", "--seed", "3", "--upside-down")
    p = run("pitvol", "measure", up, codes=(4,))
    check("PV_PIT_CHECK_OPENING_TILT" in p.stderr and "hold the scanner above the pit" in p.stderr,
          f"upside down:\n{p.stderr}")
    print("advice: too few points; an opening that faces away")

    # 6. One-line errors, exit 2 (usage) or 3 (I/O), nothing half-written.
    p = run("pitvol", "measure", pit, "--bogus", codes=(2,))
    one_line(p, "unknown option")
    p = run("pitvol", "measure", pit, "--units", "km", codes=(2,))
    one_line(p, "bad units")
    p = run("pitvol", "measure", codes=(2,))
    one_line(p, "no file")
    p = run("pitvol", "measure", pit, "--layers", os.path.join(WORK, "no", "l.csv"), codes=(3,))
    one_line(p, "--layers into a missing folder")
    p = run("pitvol", "measure", pit, "--layers", WORK, codes=(3,))
    one_line(p, "--layers onto a folder")
    p = run("pitvol", "measure", pit, "--export", pit, codes=(3,))
    one_line(p, "--export onto a file")
    if os.path.exists("/dev/full"):
        p = run("pitvol", "measure", pit, "--layers", "/dev/full", codes=(3,))
        check("No space left on device" in p.stderr, f"/dev/full: {p.stderr}")
    leftovers = [n for n in os.listdir(WORK) if ".tmp-" in n]
    check(not leftovers, f"half-written files left: {leftovers}")
    # 7. A config error: one line, the file, line, key, value and range.
    conf = os.path.join(WORK, "bad.conf")
    for text, want in (("layer_mm = 0,5\n", "bad.conf:1: layer_mm = '0,5' is not a number: write decimals "
                                            "with a point"),
                       ("\nknn_k = 99\n", "bad.conf:2: knn_k = 99 is outside the allowed 2 .. 32"),
                       ("layer_mm = 0x1\n", "bad.conf:1: layer_mm = '0x1' is not a decimal number")):
        with open(conf, "w") as f:
            f.write(text)
        p = run("pitvol", "measure", pit, "--config", conf, codes=(2,))
        one_line(p, f"config {text!r}")
        check(want in p.stderr, f"config {text!r}: {p.stderr}")
    print("errors: one line, exit 2 or 3, no temporary files left")

    # 9. The JSON (nlohmann/json) prints as the hand-written writer did:
    # one line, "key": value, ", " between fields, no fraction on a whole
    # number, coverage to 3 decimals; the help (CLI11) lists every option.
    out = run("pitvol", "measure", pit, "--json").stdout
    check(out.count("\n") == 1 and out.startswith('{"pitvol_version": "'), f"JSON line: {out}")
    j = json.loads(out)
    check('"gap_from_mm": 0, "gap_to_mm": 0, ' in out, f"whole numbers: {out}")
    check(all(round(c, 3) == c for c in j["coverage"]) and '"coverage": [1, ' in out,
          f"coverage: {j['coverage']}")
    p = run("pitvol", "measure", "--help")
    for o in ("--json", "--units", "--config", "--method", "--format", "--no-progress", "--layers",
              "--export-levelled", "--export", "exit codes"):
        check(o in p.stdout, f"--help lacks {o}:\n{p.stdout}")
    print("JSON as before, --help lists every option")
    return 0


if __name__ == "__main__":
    sys.exit(main())
