"""The shoot workflow run as CI runs it (issue 22): `rostro shoot` on four short synthetic
takes of two actors (alice wears markers, bob is bare: --markerless).

  shoot_test.py --rostro build/rostro --data data --work DIR CASE

CASE is one of: clips (render the takes and write the manifest), four_takes, second_run,
deleted_output, corrupt_source, no_snakemake. The cases after clips share DIR/out and run in
this order (tests/shoot/CMakeLists.txt chains them). Exit 77: skipped (snakemake absent).
"""

import argparse
import glob
import os
import re
import shutil
import subprocess
import sys

SKIP = 77
TAKES = {"a1": "alice", "a2": "alice", "b1": "bob", "b2": "bob"}
OUTPUTS = ("fap", "tracks.csv", "preview.mp4", "checks.json")


class Failed(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failed(message)


def run(cmd, **kw):
    print("+ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    return r


def render_clips(a):
    clips = os.path.join(a.work, "clips")
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(clips)
    # Short takes: 1 s each at 25 fps. Markers at 640x480 (identified surely), bare at 480x360.
    specs = [
        ("alice_neutral", ["--neutral-lead", "1", "--seconds", "1"]),
        ("a1", ["--neutral-lead", "0.2", "--seconds", "0.8", "--seed", "2"]),
        ("a2", ["--neutral-lead", "0.2", "--seconds", "0.8", "--seed", "3", "--head-yaw", "10"]),
        ("bob_neutral", ["--no-markers", "--size", "480x360", "--neutral-lead", "1",
                         "--seconds", "1", "--seed", "4"]),
        ("b1", ["--no-markers", "--size", "480x360", "--neutral-lead", "0.2", "--seconds", "0.8",
                "--seed", "5"]),
        ("b2", ["--no-markers", "--size", "480x360", "--neutral-lead", "0.2", "--seconds", "0.8",
                "--seed", "6"]),
    ]
    for name, args in specs:
        r = run([a.rostro, "synth", "-o", os.path.join(clips, name), *args])
        check(r.returncode == 0, f"synth {name} failed: {r.stdout}")
    layout = os.path.join(a.data, "layouts", "default.json")
    with open(os.path.join(a.work, "shoot.csv"), "w") as f:
        f.write("# four short synthetic takes of two actors (tests/shoot/shoot_test.py)\n")
        f.write("take,actor,source,layout,camera,neutral,options\n")
        f.write(f"a1,alice,clips/a1.mp4,{layout},clips/alice_neutral.intrinsics.yml,"
                "clips/alice_neutral.mp4,\n")
        f.write(f"a2,alice,clips/a2.mp4,{layout},clips/alice_neutral.intrinsics.yml,"
                "clips/alice_neutral.mp4,--method ceres\n")
        f.write("b1,bob,clips/b1.mp4,markerless,clips/bob_neutral.intrinsics.yml,"
                "clips/bob_neutral.mp4,\n")
        f.write("b2,bob,clips/b2.mp4,markerless,clips/bob_neutral.intrinsics.yml,"
                "clips/bob_neutral.mp4,\n")


def shoot(a, jobs="2"):
    return run([a.rostro, "shoot", os.path.join(a.work, "shoot.csv"), "-j", jobs, "-o",
                os.path.join(a.work, "out")])


def out(a, *parts):
    return os.path.join(a.work, "out", *parts)


def take_files(a, take):
    return [out(a, "takes", take, f"{take}.{ext}") for ext in OUTPUTS]


def mtimes(a):
    files = [f for t in TAKES for f in take_files(a, t)] + glob.glob(out(a, "actors", "*.json"))
    return {f: os.stat(f).st_mtime_ns for f in files if os.path.exists(f)}


def jobs_run(log):
    """Snakemake's 'Job stats' table of a run: rule -> count."""
    counts = {}
    m = re.search(r"Job stats:\n.*?\n-+.*?\n(.*?)\n\s*\n", log, re.S)
    if m:
        for line in m.group(1).splitlines():
            parts = line.split()
            if len(parts) >= 2 and parts[1].isdigit() and parts[0] != "total":
                counts[parts[0]] = int(parts[1])
    return counts


def report_rows(a):
    with open(out(a, "report.md")) as f:
        rows = [line for line in f if line.startswith("| ") and not line.startswith("| take ")]
    return {row.split("|")[1].strip(): [c.strip() for c in row.split("|")[1:-1]] for row in rows}


def case_four_takes(a):
    shutil.rmtree(out(a), ignore_errors=True)
    r = shoot(a)
    check(r.returncode == 0, f"the shoot failed:\n{r.stdout[-3000:]}")
    for t in TAKES:
        for f in take_files(a, t):
            check(os.path.getsize(f) > 0, f"{f} missing or empty")
    check(sorted(os.listdir(out(a, "actors"))) == ["alice.json", "bob.json"],
          f"actor profiles: {os.listdir(out(a, 'actors'))}")
    check(jobs_run(r.stdout).get("calibrate") == 2, f"calibrations: {jobs_run(r.stdout)}")
    check(jobs_run(r.stdout).get("take") == 4, f"takes: {jobs_run(r.stdout)}")
    rows = report_rows(a)
    check(sorted(rows) == sorted(TAKES), f"report rows: {sorted(rows)}")
    for t, cells in rows.items():
        check(cells[1] == TAKES[t], f"{t}: actor {cells[1]}")
        check(cells[2] in ("ok", "warn"), f"{t}: status {cells[2]}: {cells[-1]}")
        check(int(cells[3]) == 25, f"{t}: {cells[3]} frames, expected 25")
        check(float(cells[9]) > 0, f"{t}: capture fps {cells[9]}")
    check(rows["a1"][6].startswith("identified"), f"a1 identification: {rows['a1'][6]}")
    check(rows["b1"][6] == "landmarks", f"b1 identification: {rows['b1'][6]}")
    with open(out(a, "report-fps.png"), "rb") as f:
        check(f.read(8) == b"\x89PNG\r\n\x1a\n", "report-fps.png is not a PNG")


def case_second_run(a):
    before = mtimes(a)
    report = os.stat(out(a, "report.md")).st_mtime_ns
    r = shoot(a)
    check(r.returncode == 0, f"second run failed:\n{r.stdout[-3000:]}")
    check("Nothing to be done" in r.stdout, f"second run did work:\n{r.stdout[-3000:]}")
    check(mtimes(a) == before, "second run touched take outputs")
    check(os.stat(out(a, "report.md")).st_mtime_ns == report, "second run rewrote the report")


def case_deleted_output(a):
    gone = out(a, "takes", "a2", "a2.preview.mp4")
    os.remove(gone)
    before = mtimes(a)
    r = shoot(a)
    check(r.returncode == 0, f"run after deleting an output failed:\n{r.stdout[-3000:]}")
    jobs = jobs_run(r.stdout)
    check(jobs.get("take") == 1 and "calibrate" not in jobs, f"jobs run: {jobs}")
    check(os.path.getsize(gone) > 0, "the deleted preview was not made again")
    after = mtimes(a)
    for f, t in before.items():
        redone = f"{os.sep}a2{os.sep}" in f
        check(redone or after[f] == t, f"{f} was rewritten, though its take was complete")
    check(after[out(a, "takes", "a2", "a2.fap")] != before[out(a, "takes", "a2", "a2.fap")],
          "a2 was not captured again")
    check(len(report_rows(a)) == 4, "report rows after the redo")


def case_corrupt_source(a):
    source = os.path.join(a.work, "clips", "b2.mp4")
    keep = source + ".good"
    shutil.copy2(source, keep)
    try:
        with open(source, "wb") as f:
            f.write(b"\x00\x00\x00\x18ftypmp42 this is not a video" * 10)
        before = mtimes(a)
        r = shoot(a)
        check(r.returncode == 1, f"exit {r.returncode} with a corrupt take:\n{r.stdout[-3000:]}")
        check("b2" in r.stdout and "report.md" in r.stdout.splitlines()[-1],
              f"last line: {r.stdout.splitlines()[-1]}")
        after = mtimes(a)
        for f, t in before.items():
            if f"{os.sep}b2{os.sep}" not in f:
                check(after.get(f) == t, f"{f} changed, though its take is sound")
        for f in take_files(a, "b2"):
            check(not os.path.exists(f), f"{f} left behind by the failed take")
        rows = report_rows(a)
        check(sorted(rows) == sorted(TAKES), f"report rows: {sorted(rows)}")
        check(rows["b2"][2] == "failed", f"b2 status: {rows['b2'][2]}")
        check("b2.mp4" in rows["b2"][-1], f"b2's row does not name its source: {rows['b2'][-1]}")
        for t in ("a1", "a2", "b1"):
            check(rows[t][2] in ("ok", "warn"), f"{t} status {rows[t][2]}")
    finally:
        os.replace(keep, source)


def case_no_snakemake(a):
    empty = os.path.join(a.work, "empty-path")
    os.makedirs(empty, exist_ok=True)
    r = run([a.rostro, "shoot", os.path.join(a.work, "shoot.csv"), "-o", out(a)],
            env={**os.environ, "PATH": empty})
    check(r.returncode == 1, f"exit {r.returncode} without snakemake")
    lines = r.stdout.strip().splitlines()
    check(len(lines) == 1 and "snakemake not found" in lines[0] and "apt-get install snakemake"
          in lines[0], f"message: {r.stdout}")


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--rostro", required=True)
    p.add_argument("--data", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("case")
    a = p.parse_args()
    a.rostro, a.data, a.work = map(os.path.abspath, (a.rostro, a.data, a.work))
    if a.case not in ("no_snakemake", "clips") and shutil.which("snakemake") is None:
        print("SKIP: snakemake is not installed (apt-get install snakemake, Debian 12: 7.21; "
              "scripts/install-deps.sh installs it)")
        return SKIP
    cases = {"clips": render_clips, "four_takes": case_four_takes,
             "second_run": case_second_run, "deleted_output": case_deleted_output,
             "corrupt_source": case_corrupt_source, "no_snakemake": case_no_snakemake}
    try:
        cases[a.case](a)
    except Failed as e:
        print(f"FAILED: {e}")
        return 1
    print("passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
