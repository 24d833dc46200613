#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""`flexloop campaign report` on N synthetic samples: its peak memory and time (issue 54, 2.5).

The lines are a real sample's (one computed by `flexloop campaign run` on SCENE), made N: each
with its index, the plan's id, and its own figures and parameters drawn here (2 % unstable, their
closed-loop figures null as a real unstable sample's); the sigma curve is the real one's. Shards
are written as the engines write them (shard K holds i % M == K). The report runs as a child;
its peak resident set (the largest of it and its gnuplot children, wait4's ru_maxrss) and time
are printed.

    report_memory.py FLEXLOOP ROOT N [--scene S --uncertain U] [--shards M] [--keep DIR]
                     [--max-gb G] [--slope-from N0]

--max-gb G: exit 1 unless the peak is <= G GiB. --slope-from N0: also run the report on N0
samples, and require the peak projected to 10^6 samples from the two (the peak at N plus
(10^6 - N) times the memory per sample between N0 and N) to be <= G GiB: a quick suite's check
of a 10^6-sample report, whose memory grows linearly in N.
"""
import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

MILLION = 1_000_000


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def template_line(flexloop, scene, uncertain, work):
    plan = os.path.join(work, "template_plan.json")
    run([flexloop, "campaign", "plan", scene, "-u", uncertain, "-n", "2", "-o", plan])
    shard = os.path.join(work, "template.jsonl")
    run([flexloop, "campaign", "run", plan, "-o", shard, "-q"])
    with open(shard) as f:
        return json.loads(f.readline())


def sample_line(template, sigma_text, plan_id, index, rng):
    """One synthetic line: the template's keys, its own numbers."""
    s = dict(template)
    s["index"], s["plan_id"] = index, plan_id
    s["parameters"] = {k: v * (1 + 0.05 * rng.gauss(0, 1)) for k, v in template["parameters"].items()}
    unstable = rng.random() < 0.02
    s["status"] = "unstable" if unstable else "stable"
    s["spectral_radius"] = 1.0 + 0.01 * rng.random() if unstable else 0.9 + 0.09 * rng.random()
    s["natural_frequencies_hz"] = [f * (1 + 0.03 * rng.gauss(0, 1)) for f in template["natural_frequencies_hz"]]
    s["rms_open"] = {k: v * (1 + 0.1 * rng.gauss(0, 1)) for k, v in template["rms_open"].items()}
    for key in ("disk_margin_all_db", "disk_margin_all_deg", "disk_margin_db", "disk_margin_deg", "peak_sigma"):
        s[key] = None if unstable else template[key] * (1 + 0.1 * rng.gauss(0, 1))
    s["rms"] = {k: None if unstable else v * (1 + 0.1 * rng.gauss(0, 1)) for k, v in template["rms"].items()}
    s["sigma_max"] = None if unstable else "@SIGMA@"
    text = json.dumps(s, sort_keys=True, separators=(",", ":"))
    return text.replace('"@SIGMA@"', sigma_text)


def write_shards(template, plan_id, n, shards, work):
    rng = random.Random(54)
    sigma_text = json.dumps(template["sigma_max"], separators=(",", ":"))
    files = [os.path.join(work, "shard-%d.jsonl" % k) for k in range(shards)]
    outs = [open(f, "w") for f in files]
    for i in range(n):
        outs[i % shards].write(sample_line(template, sigma_text, plan_id, i, rng) + "\n")
    for f in outs:
        f.close()
    return files


def report(flexloop, args, n, template, work):
    """(peak resident set in bytes, seconds) of a report of n samples."""
    plan = os.path.join(work, "plan.json")
    run([flexloop, "campaign", "plan", args.scene, "-u", args.uncertain, "-n", str(n), "--design",
         "lhs", "-o", plan])
    with open(plan) as f:
        plan_id = json.load(f)["plan_id"]
    started = time.monotonic()
    files = write_shards(template, plan_id, n, args.shards, work)
    written = time.monotonic() - started
    cmd = [flexloop, "campaign", "report", plan, *files, "--out-dir", os.path.join(work, "out"),
           "--worst", "3"]
    started = time.monotonic()
    child = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.monotonic() - started
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("FAIL: report of %d samples exited %d" % (n, os.waitstatus_to_exitcode(status)))
    peak = usage.ru_maxrss * 1024
    size = sum(os.path.getsize(f) for f in files)
    print("N = %d: shards %.2f GB (written in %.0f s); report %.1f s, peak RSS %.0f MB (%.0f bytes a "
          "sample)" % (n, size / 1e9, written, seconds, peak / 2**20, peak / n), flush=True)
    if not args.keep:
        for f in files:
            os.remove(f)
        shutil.rmtree(os.path.join(work, "out"))
    return peak, seconds


def main():
    p = argparse.ArgumentParser()
    p.add_argument("flexloop")
    p.add_argument("root")
    p.add_argument("n", type=int)
    p.add_argument("--scene", default=None)
    p.add_argument("--uncertain", default=None)
    p.add_argument("--shards", type=int, default=4)
    p.add_argument("--keep", default=None, help="work here (kept) instead of a temporary directory")
    p.add_argument("--max-gb", type=float, default=None)
    p.add_argument("--slope-from", type=int, default=None)
    args = p.parse_args()
    args.scene = args.scene or os.path.join(args.root, "tests/fixtures/one_strut_campaign.toml")
    args.uncertain = args.uncertain or os.path.join(args.root, "tests/fixtures/one_strut_uncertain.toml")
    work = args.keep or tempfile.mkdtemp(prefix="report_memory.%d." % os.getpid())
    os.makedirs(work, exist_ok=True)
    try:
        template = template_line(args.flexloop, args.scene, args.uncertain, work)
        peak, _ = report(args.flexloop, args, args.n, template, work)
        limit = args.max_gb * 2**30 if args.max_gb else None
        if limit and peak > limit:
            sys.exit("FAIL: peak RSS %.0f MB > %.2f GiB at N = %d" % (peak / 2**20, args.max_gb, args.n))
        if limit and args.slope_from:
            small, _ = report(args.flexloop, args, args.slope_from, template, work)
            per_sample = max(0.0, (peak - small) / (args.n - args.slope_from))
            projected = peak + (MILLION - args.n) * per_sample
            print("%.0f bytes a sample from N = %d to %d: projected peak at 10^6 samples %.0f MB" %
                  (per_sample, args.slope_from, args.n, projected / 2**20))
            if projected > limit:
                sys.exit("FAIL: projected peak RSS at 10^6 samples %.0f MB > %.2f GiB" %
                         (projected / 2**20, args.max_gb))
        print("report memory: ok")
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
