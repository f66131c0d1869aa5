#!/usr/bin/env python3
"""CPU seconds of each thread of a command, read from /proc while it runs (Linux).

On a shared machine a two-thread command's wall time says little; the CPU time of its busiest
thread is what bounds its wall time on two idle cores. The threads' times are sampled every
2 ms (the kernel counts in clock ticks, 10 ms), so a thread that ends is short by one sample
at most.

Usage: tools/thread_cpu.py [--runs N] -- CMD [ARGS...]
Prints one line per run: the threads' CPU seconds, busiest first.
"""
import argparse
import os
import subprocess
import sys
import time


def thread_cpu(cmd):
    tick = os.sysconf("SC_CLK_TCK")
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    last = {}
    while proc.poll() is None:
        try:
            tids = os.listdir(f"/proc/{proc.pid}/task")
        except OSError:
            tids = []
        for tid in tids:
            try:
                with open(f"/proc/{proc.pid}/task/{tid}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            last[tid] = (int(fields[11]) + int(fields[12])) / tick  # utime + stime
        time.sleep(0.002)
    return sorted(last.values(), reverse=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("cmd", nargs=argparse.REMAINDER)
    args = ap.parse_args()
    cmd = args.cmd[1:] if args.cmd[:1] == ["--"] else args.cmd
    if not cmd:
        ap.error("no command")
    for _ in range(args.runs):
        print(" ".join(f"{s:.2f}" for s in thread_cpu(cmd)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
