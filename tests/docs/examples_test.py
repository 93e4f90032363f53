#!/usr/bin/env python3
"""Runs every example of the README and of each command's --help as written, so they stay
true (issue 23). A scratch folder is laid out like the repository root (build/ and
workflow/ linked, data/ and docs/ copied, ../shared beside it), the files the examples
name but never make are made first (a take, frames, a .pts folder, ...), and then each
example runs with bash, in the order written. An example whose input a later one makes is
tried again at the end. Examples that need what this machine lacks (a camera, a cluster,
photographs of a chessboard) are listed as skipped, with the reason.

  tests/docs/examples_test.py --rostro build/rostro --repo . --work /tmp/examples
"""

import argparse
import csv
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time

# An example containing this text is not run, for the reason given.
SKIPPED = {
    "bash scripts/bootstrap.sh": "the set-up command itself (CI runs it)",
    "ctest --test-dir build": "the test command itself",
    "/dev/video0": "needs a camera",
    "--profile workflow/profiles/slurm": "needs a Slurm cluster",
    "board_photos/": "needs photographs of a chessboard (tests/calib renders boards)",
    "chessboard_photos/": "needs photographs of a chessboard (tests/calib renders boards)",
}


def readme_examples(readme):
    """The commands of the README's ```sh blocks, continuation lines joined."""
    examples, block, in_block = [], [], False
    for line in readme.read_text().splitlines():
        if line.startswith("```"):
            in_block = not in_block and line.strip() == "```sh"
            continue
        if in_block:
            block.append(line)
    joined = ""
    for line in block:
        joined += line
        if line.rstrip().endswith("\\"):
            joined = joined.rstrip()[:-1] + " "
            continue
        if joined.strip() and not joined.strip().startswith("#"):
            examples.append(joined.strip())
        joined = ""
    return examples


def help_text(rostro, args):
    out = subprocess.run([rostro, *args, "--help"], capture_output=True, text=True)
    return out.stdout


def help_examples(rostro):
    """The 'Example:' lines of every command's and subcommand's --help."""
    examples, pending = [], [[]]
    seen = set()
    while pending:
        args = pending.pop(0)
        text = help_text(rostro, args)
        in_subcommands = in_example = False
        joined = ""
        for line in text.splitlines():
            if line.strip() in ("Subcommands:", "SUBCOMMANDS:"):
                in_subcommands = True
                continue
            if in_subcommands:
                m = re.match(r"^  (\w[\w-]*)\s", line + " ")
                if m:
                    pending.append(args + [m.group(1)])
                    continue
                in_subcommands = False
            if re.match(r"^Examples?:\s*$", line):
                in_example = True
                continue
            if in_example:
                if joined or line.startswith("  rostro "):
                    joined += line.strip()
                    if joined.endswith("\\"):
                        joined = joined[:-1] + " "
                        continue
                    if joined not in seen:
                        seen.add(joined)
                        examples.append(joined)
                    joined = ""
                    continue
                if line.strip():
                    in_example = False
    return examples


# The evaluations that run whole suites read only data/ and write only their own outputs:
# they run in a second lane beside the rest, so the check takes half the time on two cores.
SELF_CONTAINED = re.compile(r"rostro eval (suite|photos|loop|alignment)\b")


def command_key(example):
    """What an example runs, for finding repeats: the program's path, comments and a
    --markdown output (the same run, also writing a table) left out."""
    text = re.sub(r"\s+#.*$", "", example)
    text = re.sub(r"^(build/)?rostro ", "rostro ", text)
    text = re.sub(r"\s--markdown \S+", "", text)
    return " ".join(text.split())


def distinct(examples):
    """Each run once: of examples that differ only as command_key() ignores, the one with
    --markdown (which also checks the table it writes) is kept."""
    chosen = {}
    for i, (where, example) in enumerate(examples):
        key = command_key(example)
        if key not in chosen or "--markdown" in example:
            chosen[key] = i
    kept = sorted(chosen.values())
    return [examples[i] for i in kept], len(examples) - len(kept)


def skip_reason(example):
    for text, reason in SKIPPED.items():
        if text in example:
            return reason
    if re.search(r"rostro edit\b", example):
        return "interactive: waits for keys (tests/apps/window_test.cpp drives it on Xvfb)"
    if "--window" in example and "DISPLAY=" not in example:
        return "needs a display (tests/apps/window_test.cpp runs it on Xvfb)"
    return None


def x_servers():
    p = subprocess.run(["pgrep", "-x", "Xvfb"], capture_output=True, text=True)
    return set(p.stdout.split())


def make_inputs(repo, work, rostro):
    """Files examples name without making: made from the bundled sample take."""
    samples = repo / "data" / "samples"
    shutil.copy(samples / "take.mp4", work / "take.mp4")
    shutil.copy(samples / "take.mp4", work / "neutral.mp4")  # its first second is neutral
    shutil.copy(samples / "wave.fap", work / "interview.fap.tmp-4242")  # a killed capture
    (work / "frames").mkdir()
    subprocess.run(["ffmpeg", "-loglevel", "error", "-i", str(work / "take.mp4"), "-frames:v",
                    "30", str(work / "frames" / "frame_%06d.png")], check=True)
    # Starting positions: the sample's exact first frame.
    with open(samples / "take.truth.csv") as f, open(work / "start.csv", "w") as out:
        for line in f:
            if line.startswith("#") or line.startswith("frame,") or line.startswith("0,"):
                out.write(line)
    shutil.copy(samples / "take.truth.csv", work / "truth.csv")
    # What `calibrate camera board_photos/` would have written for the sample's camera.
    shutil.copy(samples / "take.intrinsics.yml", work / "camera.yml")
    (work / "poema.txt").write_text("Tudo vale a pena se a alma não é pequena.\n")
    # An MBROLA .pho: phoneme, duration in ms (and pitch points, left out).
    (work / "hola.pho").write_text("_ 100\no 90\nl 60\na 140\n_ 100\n")
    # A shoot manifest beside the examples: the example's, with paths from here.
    text = (repo / "data" / "shoot" / "example.csv").read_text()
    (work / "shoot.csv").write_text(text.replace("../", "data/"))
    # A bare face clip (face.mp4, the README's clips/bare: synth is deterministic) and its
    # truth as the iBUG .pts folder an annotator would make (annotations/).
    subprocess.run([rostro, "synth", "-o", str(work / "face"), "--no-markers",
                    "--neutral-lead", "1", "--seconds", "4"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    write_pts_folder(repo / "data" / "eval" / "ibug68_to_mpeg4.json", work / "face.truth.csv",
                     work / "annotations")


def write_pts_folder(mapping_path, truth_csv, folder):
    """The truth of a bare clip as the 68-point .pts files an annotator would write."""
    mapping = json.loads(mapping_path.read_text())
    base = mapping.get("index_base", 1)
    by_fp = {m["fp"]: m["ibug"] for m in mapping["markers"]}
    frames = {}
    with open(truth_csv) as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        for r in rows:
            frames.setdefault(int(r["frame"]), {})[r["fp"]] = (float(r["x"]), float(r["y"]))
    folder.mkdir()
    for frame, points in sorted(frames.items()):
        pts = [(0.0, 0.0)] * 68
        for fp, indices in by_fp.items():
            if fp in points:
                for i in indices:
                    pts[i - base] = points[fp]
        lines = ["version: 1", "n_points: 68", "{"]
        lines += [f"{x:.3f} {y:.3f}" for x, y in pts]
        lines.append("}")
        (folder / f"{frame:06d}.pts").write_text("\n".join(lines) + "\n")


def prepare(repo, work, rostro, shared):
    if work.exists():
        shutil.rmtree(work)
    root = work / "root"  # the examples' working folder, the repository's stand-in
    root.mkdir(parents=True)
    (root / "build").symlink_to(pathlib.Path(rostro).resolve().parent)
    (root / "workflow").symlink_to(repo / "workflow")
    shutil.copytree(repo / "data", root / "data")
    shutil.copytree(repo / "docs", root / "docs")
    if shared.exists():
        (work / "shared").symlink_to(shared.resolve())
    bin_dir = work / "bin"  # `rostro` as the README writes it, installed or not
    bin_dir.mkdir()
    (bin_dir / "rostro").symlink_to(pathlib.Path(rostro).resolve())
    make_inputs(repo, root, rostro)
    return root, bin_dir


def run(example, root, bin_dir, timeout):
    env = dict(os.environ, PATH=f"{bin_dir}:{os.environ['PATH']}")
    start = time.monotonic()
    # Output goes to a file, not a pipe: a server an example starts in the background (Xvfb)
    # keeps its descriptors open after the example ends, and a pipe would never close.
    with tempfile.TemporaryFile(mode="w+") as out:
        try:
            p = subprocess.run(["bash", "-c", "set -o pipefail; " + example], cwd=root, env=env,
                               stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                               timeout=timeout)
            code = p.returncode
        except subprocess.TimeoutExpired:
            code = -1
        out.seek(0)
        output = out.read() if code != -1 else f"still running after {timeout} s"
    return code, output, time.monotonic() - start


def same_image(a, b):
    """PSNR of two images through ffmpeg, in dB (inf when identical)."""
    p = subprocess.run(["ffmpeg", "-loglevel", "info", "-i", str(a), "-i", str(b), "-lavfi",
                        "psnr", "-f", "null", "-"], capture_output=True, text=True)
    m = re.search(r"average:(inf|[\d.]+)", p.stderr)
    return float(m.group(1)) if m else 0.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rostro", required=True)
    ap.add_argument("--repo", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--only", default="", help="run only examples containing this text")
    a = ap.parse_args()
    repo = pathlib.Path(a.repo).resolve()
    shared = repo.parent / "shared"
    work = pathlib.Path(a.work).resolve()
    rostro = str(pathlib.Path(a.rostro).resolve())

    examples = [("README", e) for e in readme_examples(repo / "README.md")]
    examples += [("--help", e) for e in help_examples(rostro)]
    if a.only:
        examples = [(w, e) for w, e in examples if a.only in e]
    examples, repeats = distinct(examples)
    root, bin_dir = prepare(repo, work, rostro, shared)

    lock = threading.Lock()
    failed, skipped, passed = [], [], [0]

    def say(text):
        with lock:
            print(text, flush=True)

    def run_lane(lane):
        for where, example in lane:
            reason = skip_reason(example)
            if reason is None and "../shared" in example and not shared.exists():
                reason = "../shared is absent"
            if reason:
                skipped.append((where, example, reason))
                say(f"skip  {where}: {example}\n      ({reason})")
                continue
            code, output, seconds = run(example, root, bin_dir, a.timeout)
            if code == 0:
                passed[0] += 1
                say(f"ok    {seconds:5.1f} s  {where}: {example}")
            else:
                failed.append((where, example))
                say(f"later {where}: {example} (exit {code}; tried again at the end)")

    servers_before = x_servers()
    suites = [e for e in examples if SELF_CONTAINED.search(e[1])]
    second_lane = threading.Thread(target=run_lane, args=(suites,))
    second_lane.start()
    run_lane([e for e in examples if not SELF_CONTAINED.search(e[1])])
    second_lane.join()
    # Inputs a later example makes are there now.
    still_failing = []
    for where, example in failed:
        code, output, seconds = run(example, root, bin_dir, a.timeout)
        if code == 0:
            passed[0] += 1
            print(f"ok    {seconds:5.1f} s  {where}: {example}", flush=True)
        else:
            still_failing.append(example)
            tail = "\n".join(output.strip().splitlines()[-6:])
            print(f"FAIL  exit {code}  {where}: {example}\n{tail}\n", flush=True)

    # An X server an example started for a window example is stopped with the check.
    for pid in x_servers() - servers_before:
        subprocess.run(["kill", pid])

    # The README's contact sheet is what `rostro pose --sheet` makes today.
    sheet = root / "docs" / "images" / "contact-sheet.png"
    committed = repo / "docs" / "images" / "contact-sheet.png"
    if any("pose --sheet" in e and "docs/images/contact-sheet.png" in e for _, e in examples):
        psnr = same_image(sheet, committed)
        if psnr < 40:
            still_failing.append("pose --sheet")
            print(f"FAIL  docs/images/contact-sheet.png differs from what the README's "
                  f"pose --sheet makes (PSNR {psnr:.1f} dB < 40): commit the new one")
        else:
            print(f"ok    the committed contact sheet is reproduced (PSNR {psnr} dB)")

    print(f"\n{passed[0]} examples ran ({repeats} repeats run once), {len(skipped)} skipped, "
          f"{len(still_failing)} failed")
    return 1 if still_failing else 0


if __name__ == "__main__":
    sys.exit(main())
