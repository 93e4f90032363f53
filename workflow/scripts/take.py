"""One take of a shoot: 'rostro capture', then the checks a supervisor reads (docs/shoot.md).

Runs rostro capture (it writes the .fap, tracks and preview atomically), times it, then
reads back what it wrote: 'rostro fap validate' and 'rostro fap info' for the FAP ranges,
the tracks CSV for frames, dropped frames (gaps in the container's timestamps), lost markers
and the identification line. Writes TAKE.checks.json atomically, last, so its presence means
the take is complete. A failing capture prints rostro's error and exits 1.
"""

import argparse
import csv
import json
import os
import re
import resource
import subprocess
import sys
import time


# The thresholds of the flags; workflow/config.yaml sets them per shoot.
DEFAULT_LIMITS = {
    "max_dropped_frames": 0,  # frames missing from the container's timestamps
    "max_lost_share": 0.1,  # share of marker-frames (landmark-frames) written invalid
    "max_frames_without_face": 0,  # frames in which no marker or landmark was found
    "min_identification_margin": 0.3,  # the margin 'rostro capture' prints (markers only)
    "fap_limit_fapu": 1024,  # |value| in FAPU: one whole reference distance
    "fap_limit_au": 104720,  # |value| in AU (1e-5 rad): 60 degrees
}


def fail(take, message):
    print(f"take {take} failed: {message}", file=sys.stderr)
    sys.exit(1)


def run(cmd):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def last_line(text):
    lines = [line for line in text.splitlines() if line.strip()]
    return lines[-1].strip() if lines else "(no message)"


def read_tracks(path, fps):
    """Frames, dropped frames, lost marker-frames and the worst markers of a tracks CSV."""
    times = {}
    valid_by_marker, total_by_marker = {}, {}
    valid_in_frame = {}
    identification = ""
    with open(path, newline="") as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            frame = int(row["frame"])
            times[frame] = float(row["time_s"])
            ok = row["valid"] == "1"
            m = row["marker"]
            total_by_marker[m] = total_by_marker.get(m, 0) + 1
            valid_by_marker[m] = valid_by_marker.get(m, 0) + ok
            valid_in_frame[frame] = valid_in_frame.get(frame, 0) + ok
    with open(path) as f:
        for line in f:
            if line.startswith("# identification:"):
                identification = line.split(":", 1)[1].strip()
                break
    frames = sorted(times)
    dropped = 0
    step = 1.0 / fps if fps > 0 else 0
    for a, b in zip(frames, frames[1:]):
        gap = times[b] - times[a]
        if step and gap > 1.5 * step:
            dropped += int(round(gap / step)) - 1
    total = sum(total_by_marker.values())
    valid = sum(valid_by_marker.values())
    lost_by_marker = {m: total_by_marker[m] - valid_by_marker[m] for m in total_by_marker}
    worst = sorted((m for m in lost_by_marker if lost_by_marker[m] > 0),
                   key=lambda m: (-lost_by_marker[m], m))[:3]
    return {
        "frames": len(frames),
        "dropped_frames": dropped,
        "marker_frames": total,
        "lost_marker_frames": total - valid,
        "lost_share": (total - valid) / total if total else 1.0,
        "frames_without_face": sum(1 for fr in frames if valid_in_frame.get(fr, 0) == 0),
        "worst_markers": {m: lost_by_marker[m] for m in worst},
        "identification": identification,
    }


INFO_HEADER = re.compile(r"^\s*FAP\s+name\s+unit\s+frames\s+min\s+max\s*$")


def read_fap_info(text):
    """fps, frames, duration and each FAP's range from 'rostro fap info'."""
    info = {"faps": {}}
    in_table = False
    for line in text.splitlines():
        if INFO_HEADER.match(line):
            in_table = True
            continue
        if in_table:
            parts = line.split()
            if len(parts) == 6 and parts[0].isdigit():
                info["faps"][parts[1]] = {"id": int(parts[0]), "unit": parts[2],
                                          "frames": int(parts[3]), "min": float(parts[4]),
                                          "max": float(parts[5])}
            continue
        key, _, value = line.partition(" ")
        value = value.strip()
        if key == "fps":
            info["fps"] = float(value)
        elif key == "frames":
            info["frames"] = int(value.split()[0])
        elif key == "duration":
            info["duration_s"] = float(value.split()[0])
    if "fps" not in info or "frames" not in info:
        raise ValueError("unexpected 'rostro fap info' output: " + last_line(text))
    return info


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--rostro", required=True)
    p.add_argument("--take", required=True)
    p.add_argument("--source", required=True)
    p.add_argument("--profile", required=True)
    p.add_argument("--layout", required=True, help="a marker layout JSON or 'markerless'")
    p.add_argument("--camera", default="")
    p.add_argument("--options", default="[]", help="extra capture options, a JSON list")
    p.add_argument("--fap", required=True)
    p.add_argument("--tracks", required=True)
    p.add_argument("--preview", required=True)
    p.add_argument("--checks", required=True)
    p.add_argument("--limits", default="{}", help="check thresholds, JSON (config.yaml)")
    a = p.parse_args()
    limits = {**DEFAULT_LIMITS, **json.loads(a.limits)}

    if not os.path.exists(a.source):
        fail(a.take, f"{a.source}: the source does not exist")
    tracker = ["--markerless"] if a.layout == "markerless" else ["--layout", a.layout]
    cmd = [a.rostro, "capture", a.source, *tracker, "--actor", a.profile]
    if a.camera:
        cmd += ["--camera", a.camera]
    cmd += ["-o", a.fap, "--tracks", a.tracks, "--preview", a.preview, *json.loads(a.options)]
    print("+ " + " ".join(cmd), file=sys.stderr, flush=True)
    start = time.monotonic()
    capture = run(cmd)
    wall = time.monotonic() - start
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    sys.stderr.write(capture.stderr)
    sys.stdout.write(capture.stdout)
    if capture.returncode != 0:
        fail(a.take, last_line(capture.stderr))
    # A capture stopped by a signal keeps the frames so far and exits 0: for a shoot that is
    # an unfinished take, to be redone, not a short one.
    if "(stopped by " in capture.stdout:
        fail(a.take, "the capture was stopped by a signal before the end of the take; run the "
             "shoot again to redo it")

    validate = run([a.rostro, "fap", "validate", a.fap])
    info_run = run([a.rostro, "fap", "info", a.fap])
    if info_run.returncode != 0:
        fail(a.take, "rostro fap info: " + last_line(info_run.stderr))
    info = read_fap_info(info_run.stdout)
    tracks = read_tracks(a.tracks, info["fps"])

    # The supervisor's flags: each names what is off and by how much.
    flags = []
    if validate.returncode != 0:
        flags.append("fap validate: " + last_line(validate.stdout + validate.stderr))
    if tracks["frames"] != info["frames"]:
        flags.append(f"{tracks['frames']} tracked frames but {info['frames']} FAP frames")
    if tracks["dropped_frames"] > limits["max_dropped_frames"]:
        flags.append(f"{tracks['dropped_frames']} dropped frames")
    if tracks["lost_share"] > limits["max_lost_share"]:
        flags.append(f"{100 * tracks['lost_share']:.1f} % marker-frames lost")
    if tracks["frames_without_face"] > limits["max_frames_without_face"]:
        flags.append(f"{tracks['frames_without_face']} frames with no marker or face found")
    beyond = []
    for name, r in info["faps"].items():
        limit = limits["fap_limit_au" if r["unit"] == "AU" else "fap_limit_fapu"]
        extreme = max(abs(r["min"]), abs(r["max"]))
        if extreme > limit:
            beyond.append(f"{name} {r['min']:g}..{r['max']:g}")
    if beyond:
        flags.append("FAPs beyond the limit: " + ", ".join(beyond))
    ident = tracks["identification"]
    margin = re.search(r"margin ([0-9.]+)", ident)
    if margin and float(margin.group(1)) < limits["min_identification_margin"]:
        flags.append(f"unsure identification (margin {margin.group(1)})")

    checks = {
        "take": a.take,
        "status": "warn" if flags else "ok",
        "flags": flags,
        "fps": info["fps"],
        "frames": info["frames"],
        "duration_s": info.get("duration_s", info["frames"] / info["fps"]),
        "capture_s": round(wall, 3),
        "capture_fps": round(info["frames"] / wall, 2) if wall > 0 else 0,
        "cpu_s": round(usage.ru_utime + usage.ru_stime, 3),
        "max_rss_mb": round(usage.ru_maxrss / 1024, 1),
        "faps_used": len(info["faps"]),
        "fap_ranges": info["faps"],
        "identification": ident or ("landmarks" if a.layout == "markerless" else ""),
        **{k: tracks[k] for k in ("dropped_frames", "marker_frames", "lost_marker_frames",
                                  "lost_share", "frames_without_face", "worst_markers")},
    }
    tmp = f"{a.checks}.tmp-{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(checks, f, indent=1)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, a.checks)
    print(f"take {a.take}: {checks['status']}, {info['frames']} frames in {wall:.1f} s"
          + ("; " + "; ".join(flags) if flags else ""), file=sys.stderr)


if __name__ == "__main__":
    main()
