#!/usr/bin/python3
"""Headless LinuxCNC display: on, auto, run $LCNC_PROGRAM with the 1 ms sampler on, then quit."""
import json
import os
import subprocess
import sys
import time

import linuxcnc

prog, out = os.environ["LCNC_PROGRAM"], os.environ["LCNC_SAMPLES"]
info = {"errors": []}


def halcmd(*args):
    return subprocess.run(["halcmd", *args], capture_output=True, text=True).stdout.strip()


def drain_errors(err):
    while (m := err.poll()):
        info["errors"].append(m[1])


def wait_for(pred, what, timeout=20.0):
    t0 = time.time()
    while time.time() - t0 < timeout:
        s.poll()
        if pred():
            return
        time.sleep(0.01)
    raise SystemExit(f"display.py: timed out waiting for {what}")


for _ in range(200):  # task may not be up yet
    try:
        s, c, e = linuxcnc.stat(), linuxcnc.command(), linuxcnc.error_channel()
        s.poll()
        break
    except linuxcnc.error:
        time.sleep(0.05)
c.state(linuxcnc.STATE_ESTOP_RESET)
c.state(linuxcnc.STATE_ON)
wait_for(lambda: s.task_state == linuxcnc.STATE_ON, "machine on")
c.mode(linuxcnc.MODE_AUTO)
wait_for(lambda: s.task_mode == linuxcnc.MODE_AUTO, "auto mode")
c.program_open(prog)
c.wait_complete()
with open(out, "w") as f:
    sampler = subprocess.Popen(["halsampler", "-t"], stdout=f)
    time.sleep(0.2)
    halcmd("setp", "sampler.0.enable", "1")
    t0 = time.time()
    c.auto(linuxcnc.AUTO_RUN, 0)
    wait_for(lambda: s.interp_state != linuxcnc.INTERP_IDLE, "program start")
    wait_for(lambda: s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and s.inpos,
             "program end", timeout=600)
    info["wall_s"] = time.time() - t0
    time.sleep(0.3)  # some idle samples after the end
    halcmd("setp", "sampler.0.enable", "0")
    wait_for(lambda: halcmd("getp", "sampler.0.curr-depth") == "0", "sampler drained")
    time.sleep(0.2)
    sampler.terminate()
    sampler.wait()
for pin in ("sampler.0.overruns", "motion-controller.tmax", "motion-command-handler.tmax",
            "servo-thread.tmax", "sampler.0.curr-depth"):
    info[pin] = halcmd("getp", pin)
drain_errors(e)
info["version"] = os.environ.get("LINUXCNCVERSION", "")
with open(out + ".json", "w") as f:
    json.dump(info, f, indent=1)
c.state(linuxcnc.STATE_OFF)
sys.exit(0)
