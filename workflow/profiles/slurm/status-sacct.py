#!/usr/bin/env python3
"""Snakemake --cluster-status for Slurm: prints running, success or failed for a job id.

Snakemake 7 otherwise waits forever for a job that Slurm killed (time limit, out of memory,
node failure), since the job never reports back. Uses sacct, then scontrol for jobs sacct
does not know yet.
"""
import subprocess
import sys

RUNNING = {"PENDING", "RUNNING", "CONFIGURING", "COMPLETING", "REQUEUED", "RESIZING",
           "SUSPENDED", "PREEMPTED"}


def state(job):
    try:
        out = subprocess.run(["sacct", "-j", job, "--format=State", "--noheader", "-X",
                              "--parsable2"], capture_output=True, text=True, timeout=30).stdout
        if out.strip():
            return out.split()[0].split("+")[0]
        out = subprocess.run(["scontrol", "show", "job", job], capture_output=True, text=True,
                             timeout=30).stdout
        for field in out.split():
            if field.startswith("JobState="):
                return field.split("=", 1)[1]
    except (OSError, subprocess.TimeoutExpired):
        pass
    return "PENDING"  # unknown for now: ask again later


def main():
    s = state(sys.argv[1])
    print("success" if s == "COMPLETED" else "running" if s in RUNNING else "failed")


if __name__ == "__main__":
    main()
