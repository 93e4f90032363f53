"""The shoot report: report.md (one row per take of the manifest, in its order) and
report-fps.png (capture frames per second per take). Both written atomically.

A take with TAKE.checks.json is done ("ok", or "warn" with the supervisor's flags). With
--partial (the workflow's error handler) a take without one is "failed" with the last line
of its log, or "not run" with the reason (its actor's calibration failed, or the run stopped
before it).
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import manifest as shoot_manifest  # noqa: E402


def last_line(path):
    try:
        with open(path, errors="replace") as f:
            lines = [line.strip() for line in f if line.strip()]
    except OSError:
        return ""
    for line in reversed(lines):
        if line.startswith("take ") and " failed: " in line:
            return line.split(" failed: ", 1)[1]
    return lines[-1] if lines else ""


def newer(path, than):
    try:
        return os.path.getmtime(path) > os.path.getmtime(than)
    except OSError:
        return False


def row_of(take, out):
    """What the report says about one take."""
    checks = os.path.join(out, "takes", take.take, f"{take.take}.checks.json")
    profile = (take.neutral if take.neutral.endswith(".json")
               else os.path.join(out, "actors", f"{take.actor}.json"))
    if os.path.exists(checks) and not newer(take.source, checks) and not newer(profile, checks):
        with open(checks) as f:
            return json.load(f)
    row = {"take": take.take, "flags": []}
    log = os.path.join(out, "logs", "takes", f"{take.take}.log")
    calibration_log = os.path.join(out, "logs", "calibrate", f"{take.actor}.log")
    if not os.path.exists(profile):
        reason = last_line(calibration_log) or "no actor profile"
        row.update(status="not run", flags=[f"calibration of {take.actor} failed: {reason}"])
    elif os.path.exists(log) and (not os.path.exists(checks) or newer(log, checks)):
        row.update(status="failed", flags=[last_line(log) or "see " + log])
    else:
        row.update(status="not run", flags=["the run stopped before this take"])
    return row


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def write_atomic(path, write):
    tmp = f"{path}.tmp-{os.getpid()}"
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def markdown(takes, rows, manifest):
    done = [r for r in rows if r["status"] in ("ok", "warn")]
    count = {s: sum(r["status"] == s for r in rows) for s in ("ok", "warn", "failed", "not run")}
    frames = sum(r["frames"] for r in done)
    capture_s = sum(r["capture_s"] for r in done)
    lines = [
        "# Shoot report",
        "",
        f"Manifest: `{manifest}`. {len(rows)} takes: {count['ok']} ok, {count['warn']} "
        f"with flags, {count['failed']} failed, {count['not run']} not run. Captured "
        f"{frames} frames ({sum(r['duration_s'] for r in done):.1f} s of takes) in "
        f"{capture_s:.1f} s of capture time.",
        "",
        "Frames per second of each capture: report-fps.png. Columns: docs/shoot.md, "
        "\"The checks and the report\".",
        "",
        "| take | actor | status | frames | dropped | lost markers | identification | "
        "FAPs (widest range) | capture s | fps | MB | flags |",
        "|---|---|---|---:|---:|---:|---|---|---:|---:|---:|---|",
    ]
    for t, r in zip(takes, rows):
        if r["status"] in ("ok", "warn"):
            widest = max(r["fap_ranges"].items(), default=None,
                         key=lambda kv: (kv[1]["unit"] != "AU", kv[1]["max"] - kv[1]["min"]))
            fap = f"{r['faps_used']} ({widest[0]} {widest[1]['min']:g}..{widest[1]['max']:g})" \
                if widest else "0"
            lost = f"{r['lost_marker_frames']} ({100 * r['lost_share']:.1f} %)"
            worst = ", ".join(f"{m} {n}" for m, n in r["worst_markers"].items())
            if worst:
                lost += f": {worst}"
            lines.append(
                f"| {t.take} | {t.actor} | {r['status']} | {r['frames']} | "
                f"{r['dropped_frames']} | {cell(lost)} | {cell(r['identification'])} | "
                f"{cell(fap)} | {r['capture_s']:.1f} | {r['capture_fps']:.1f} | "
                f"{r['max_rss_mb']:.0f} | {cell('; '.join(r['flags']))} |")
        else:
            lines.append(f"| {t.take} | {t.actor} | {r['status']} | | | | | | | | | "
                         f"{cell('; '.join(r['flags']))} |")
    return "\n".join(lines) + "\n"


def plot(takes, rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [t.take for t in takes]
    fps = [r.get("capture_fps", 0) if r["status"] in ("ok", "warn") else 0 for r in rows]
    colours = {"ok": "tab:green", "warn": "tab:orange"}
    fig, ax = plt.subplots(figsize=(max(6, 0.5 * len(names) + 2), 3.5), dpi=100)
    ax.bar(range(len(names)), fps, color=[colours.get(r["status"], "tab:red") for r in rows])
    for i, r in enumerate(rows):
        if r["status"] not in ("ok", "warn"):
            ax.text(i, 0, r["status"], rotation=90, ha="center", va="bottom", color="tab:red")
    source_fps = [r["fps"] for r in rows if "fps" in r]
    if source_fps:
        ax.axhline(max(source_fps), color="grey", linestyle="--", linewidth=1,
                   label=f"take frame rate ({max(source_fps):g} fps)")
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=45 if len(names) > 6 else 0, ha="right"
                       if len(names) > 6 else "center", fontsize=8)
    ax.set_ylabel("capture frames per second")
    ax.set_title("Capture speed per take (green ok, orange flagged, red failed)", fontsize=9)
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, format="png"))
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--manifest", required=True)
    p.add_argument("--out", required=True, help="the shoot's output folder")
    p.add_argument("--partial", action="store_true",
                   help="takes may be missing (failed or not run): say so in their rows")
    a = p.parse_args()
    takes = list(shoot_manifest.read(a.manifest).values())
    rows = [row_of(t, a.out) for t in takes]
    if not a.partial:
        missing = [r["take"] for r in rows if r["status"] not in ("ok", "warn")]
        if missing:
            sys.exit(f"report: takes without checks: {', '.join(missing)}")

    def write_md(tmp):
        with open(tmp, "w") as f:
            f.write(markdown(takes, rows, a.manifest))

    write_atomic(os.path.join(a.out, "report.md"), write_md)
    plot(takes, rows, os.path.join(a.out, "report-fps.png"))
    bad = [r for r in rows if r["status"] in ("failed", "not run")]
    print(f"report: {len(rows)} takes, {len(bad)} failed or not run: "
          f"{os.path.join(a.out, 'report.md')}", file=sys.stderr)


if __name__ == "__main__":
    main()
