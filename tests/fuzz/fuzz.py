#!/usr/bin/env python3
"""Fuzz driver for paramorph_native (issue 19): random and mutated meshes and
options through every public function (the table in cases.py), each call in a
child process with a time limit.

An outcome is fine when the call returns, raises one of the module's typed
errors (a MeshError subclass; Cancelled when the callback asked to stop;
DeviceError, a ComputeError, for an OpenCL failure) or pybind11's TypeError
for arguments of the wrong Python type. Findings: a signal or sanitizer abort (the worker
dies), a call over the time limit, and any other exception (RuntimeError,
MemoryError, IndexError, a plain ValueError ...). Each finding is saved as a
case file (seed, index, target, arguments) under --out/findings and replays
alone with --replay. Exit status: 0 without findings, 1 with, 2 on usage or
harness errors.

  tests/fuzz/fuzz.py --seconds 120 --seed 1          # a bounded run
  tests/fuzz/fuzz.py --only sphere_map,morph --cases 200
  tests/fuzz/fuzz.py --replay fuzz-out/findings/0003-simplify-untyped.pkl
  tests/fuzz/fuzz.py --replay tests/fuzz/findings     # every past finding (the gate)
  tests/fuzz/fuzz.py --build-dir build-asan ...      # the sanitizer build (README)

The cases depend only on (seed, index, target): a run with the same seed and
--only makes the same cases in the same order; --seconds decides how many.
"""
import argparse
import json
import os
import pickle
import re
import select
import signal
import struct
import subprocess
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))

import cases  # noqa: E402
from specs import describe  # noqa: E402

WORKER = HERE / "worker.py"
FINDING_STATUSES = ("crash", "timeout", "untyped")
SANITIZER_OPTIONS = {
    # Python itself is not instrumented: its own leaks are not ours, and a
    # report must stop the worker so the driver sees it as a crash.
    "ASAN_OPTIONS": "detect_leaks=0:abort_on_error=1:halt_on_error=1:allocator_may_return_null=1:"
                    "detect_stack_use_after_return=0:handle_segv=1:symbolize=1",
    "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1:abort_on_error=1",
}


def module_dir(build_dir):
    path = Path(build_dir)
    if not path.is_absolute():
        path = REPO / path
    return path / "python"


def sanitized(build_dir):
    """True when build_dir was configured with -fsanitize=address (scripts/build-sanitized.sh)."""
    cache = module_dir(build_dir).parent / "CMakeCache.txt"
    return cache.exists() and "fsanitize=address" in cache.read_text(errors="replace")


def gcc_library(name):
    out = subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True)
    path = out.stdout.strip()
    if not path or not Path(path).exists():
        sys.exit(f"fuzz: the build is sanitized but gcc -print-file-name={name} found nothing")
    return str(Path(path).resolve())


def asan_preload():
    """libasan first (Python is not instrumented), then libstdc++: Python does not
    link it, and without it loaded when ASan starts, ASan's __cxa_throw
    interceptor finds no real __cxa_throw and every C++ exception aborts."""
    return f"{gcc_library('libasan.so')}:{gcc_library('libstdc++.so')}"


def worker_environment(build_dir):
    env = dict(os.environ)
    env.update(cases.environment_defaults())
    env.setdefault("PYTHONFAULTHANDLER", "1")
    if sanitized(build_dir):
        env["LD_PRELOAD"] = asan_preload()
        for name, value in SANITIZER_OPTIONS.items():
            env[name] = env.get(name) or value
    return env


class Worker:
    """One child process running cases in turn; replaced when it dies or hangs."""

    def __init__(self, build_dir, log_path, memory_limit_mb):
        self.log_path = log_path
        self.log = open(log_path, "ab")
        limit = 0 if sanitized(build_dir) else memory_limit_mb  # ASan reserves terabytes of address space
        self.proc = subprocess.Popen(
            [sys.executable, str(WORKER), str(module_dir(build_dir)), "--memory-limit-mb", str(limit)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.log,
            env=worker_environment(build_dir), start_new_session=True)
        self.served = 0

    def _read_exact(self, n, deadline):
        data = b""
        fd = self.proc.stdout.fileno()
        while len(data) < n:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            ready, _, _ = select.select([fd], [], [], left)
            if not ready:
                return None
            chunk = os.read(fd, n - len(data))
            if not chunk:
                return b""  # EOF: the worker died
            data += chunk
        return data

    def run(self, case, timeout):
        """The worker's outcome dict, or a crash / timeout outcome made here."""
        self.log.flush()
        log_offset = os.path.getsize(self.log_path)
        start = time.monotonic()
        payload = pickle.dumps(case)
        try:
            self.proc.stdin.write(struct.pack("<I", len(payload)) + payload)
            self.proc.stdin.flush()
        except BrokenPipeError:
            pass
        deadline = start + timeout
        head = self._read_exact(4, deadline)
        body = self._read_exact(struct.unpack("<I", head)[0], deadline + 5) if head else head
        self.served += 1
        if body:
            return pickle.loads(body)
        seconds = time.monotonic() - start
        if head is None or body is None:
            self.kill()
            return {"status": "timeout", "seconds": seconds, "limit": timeout,
                    "stderr": self.stderr_since(log_offset)}
        code = self.proc.wait()
        if code < 0:
            what = signal.Signals(-code).name
        else:
            what = f"exit status {code}"
        return {"status": "crash", "error": what, "seconds": seconds,
                "stderr": self.stderr_since(log_offset)}

    def stderr_since(self, offset, limit=20000):
        self.log.flush()
        with open(self.log_path, "rb") as f:
            f.seek(offset)
            text = f.read().decode(errors="replace")
        return text if len(text) <= limit else text[:4000] + "\n...\n" + text[-(limit - 4000):]

    def kill(self):
        if self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        self.proc.wait()

    def close(self):
        if self.proc.poll() is None:
            try:
                self.proc.stdin.close()
                self.proc.wait(timeout=10)
            except (BrokenPipeError, subprocess.TimeoutExpired):
                self.kill()
        self.log.close()


CRASH_LINES = re.compile(r"(ERROR: AddressSanitizer: [\w-]+|runtime error: .*|Assertion .* failed|"
                         r"terminate called .*|what\(\): .*|Fatal Python error: \w+)")


def crash_reason(stderr):
    """The line of a dead worker's stderr that says why (sanitizer, assertion, terminate)."""
    found = CRASH_LINES.findall(stderr or "")
    specific = [f for f in found if not f.startswith("Fatal Python error")]
    return (specific or found or [""])[0][:200]


def slow_budget(case):
    """A case that asked for a huge amount of work (an iteration budget over 1e5):
    running past the time limit is then what it asked for, not a hang."""
    return any(name in cases.BUDGET_OPTIONS and isinstance(value, int) and not isinstance(value, bool)
               and value > 10 ** 5 for name, value in case["kwargs"].items())


def settle(case, outcome):
    """Adds why a worker died, and tells a budget's slow run from a hang."""
    if outcome["status"] == "crash":
        outcome["why"] = crash_reason(outcome.get("stderr"))
    if outcome["status"] == "timeout" and slow_budget(case):
        outcome["status"] = "slow_budget"
    return outcome


def known(case, outcome):
    """The KNOWN_FINDINGS entry a finding matches, or None."""
    for target, error, pattern, why in cases.KNOWN_FINDINGS:
        if case["target"] == target and outcome.get("error") == error and \
                re.search(pattern, outcome.get("message", "")):
            return why
    return None


def signature(case, outcome):
    """What makes two findings the same: target, status, error and its message
    with numbers blanked."""
    message = (outcome.get("message") or outcome.get("reason") or outcome.get("why") or "").split("\n")[0]
    message = re.sub(r"[-+]?\d[\d.e+-]*", "#", message)[:100]
    return f"{case['target']} | {outcome['status']} | {outcome.get('error', '')} | {message}"


def describe_case(case):
    args = ", ".join(describe(a) for a in case["args"])
    kwargs = ", ".join(f"{k}={describe(v)}" for k, v in case["kwargs"].items())
    return f"{case['target']}({', '.join(x for x in (args, kwargs) if x)})"


def save_finding(out, number, case, outcome, replay_prefix):
    findings = out / "findings"
    findings.mkdir(parents=True, exist_ok=True)
    stem = f"{number:04d}-{case['target'].replace('.', '_')}-{outcome['status']}"
    with open(findings / f"{stem}.pkl", "wb") as f:
        pickle.dump({"case": case, "outcome": outcome}, f)
    text = [f"target:   {case['target']}",
            f"seed:     {case['seed']}  index: {case['index']}",
            f"notes:    {'; '.join(case['notes'])}",
            f"call:     {describe_case(case)}",
            f"status:   {outcome['status']} {outcome.get('error', '')} {outcome.get('reason', '')} "
            f"{outcome.get('why', '')}",
            f"message:  {outcome.get('message', '')}",
            f"stage:    {outcome.get('stage', 'call')}",
            f"seconds:  {outcome.get('seconds', 0):.2f}",
            f"alone:    {outcome.get('reproduced_alone', 'not rerun')}",
            f"replay:   {replay_prefix} --replay {findings / (stem + '.pkl')}"]
    if outcome.get("stderr"):
        text += ["", "--- worker stderr from this case ---", outcome["stderr"]]
    (findings / f"{stem}.txt").write_text("\n".join(text) + "\n")
    return findings / f"{stem}.pkl"


def replay_prefix(args):
    prefix = f"{sys.executable} {os.path.relpath(__file__, os.getcwd())}"
    if args.build_dir != default_build_dir():
        prefix += f" --build-dir {args.build_dir}"
    return prefix


def default_build_dir():
    return os.environ.get("PARAMORPH_BUILD_DIR", "build")


def fuzz(args):
    targets = sorted(cases.TABLE)
    if args.only:
        wanted = [t.strip() for t in args.only.split(",") if t.strip()]
        unknown = [t for t in wanted if t not in cases.TABLE]
        if unknown:
            print(f"fuzz: unknown target(s) {', '.join(unknown)}; known: {', '.join(targets)}", file=sys.stderr)
            return 2
        targets = sorted(wanted)
    if not (module_dir(args.build_dir)).is_dir():
        print(f"fuzz: no module folder {module_dir(args.build_dir)} (build first)", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    log_path = out / "worker.log"
    log_path.write_bytes(b"")
    prefix = replay_prefix(args)
    print(f"fuzz: seed {args.seed}, {len(targets)} targets, {args.seconds:g} s, module "
          f"{module_dir(args.build_dir)}{' (ASan/UBSan)' if sanitized(args.build_dir) else ''}, out {out}",
          flush=True)
    per_target = defaultdict(Counter)
    per_signature = {}
    seconds_per_target = Counter()
    slowest = []
    harness_errors = []
    slow_budgets = []
    nonfinite = Counter()
    nonfinite_examples = []
    known_findings = {}
    worker = None
    start = time.monotonic()
    index = 0
    saved = 0
    restarts = 0
    schedule = cases.schedule(args.seed, targets)
    try:
        while time.monotonic() - start < args.seconds and (args.cases is None or index < args.cases):
            _, target = next(schedule)
            case = cases.make_case(args.seed, index, target)
            index += 1
            if worker is None or worker.served >= args.recycle:
                if worker is not None:
                    worker.close()
                worker = Worker(args.build_dir, log_path, args.memory_limit_mb)
            outcome = worker.run(case, args.call_timeout)
            status = settle(case, outcome)["status"]
            if status in ("crash", "timeout", "slow_budget"):
                worker.close()
                worker = None
                restarts += 1
                if status == "crash" and args.confirm:
                    alone = Worker(args.build_dir, log_path, args.memory_limit_mb)
                    again = alone.run(case, args.call_timeout)
                    alone.close()
                    outcome["reproduced_alone"] = again["status"] == status
            why_known = known(case, outcome) if status in FINDING_STATUSES else None
            if why_known:
                entry = known_findings.setdefault(signature(case, outcome),
                                                  {"count": 0, "why": why_known, "call": describe_case(case)})
                entry["count"] += 1
                outcome["status"] = status = "known"
            per_target[target][status] += 1
            seconds_per_target[target] += outcome.get("seconds", 0.0)
            slowest.append((outcome.get("seconds", 0.0), target, index - 1))
            slowest = sorted(slowest, reverse=True)[:5]
            if outcome.get("nonfinite"):
                nonfinite[target] += 1
                if len(nonfinite_examples) < 20:
                    nonfinite_examples.append(f"{target} #{index - 1}: {', '.join(outcome['nonfinite'])} "
                                              f"from {describe_case(case)}"[:400])
            if status == "slow_budget":
                slow_budgets.append(f"{target} #{index - 1}: {describe_case(case)}"[:300])
            if status == "harness_error":
                harness_errors.append(f"{target} #{index - 1}: {outcome.get('error')}: {outcome.get('message')}")
            if status in FINDING_STATUSES:
                key = signature(case, outcome)
                entry = per_signature.setdefault(key, {"count": 0, "cases": [], "first": None})
                entry["count"] += 1
                if len(entry["cases"]) < args.keep_per_signature:
                    saved += 1
                    path = save_finding(out, saved, case, outcome, prefix)
                    entry["cases"].append(str(path))
                    if entry["first"] is None:
                        entry["first"] = {"call": describe_case(case), "notes": case["notes"],
                                          "message": outcome.get("message", ""),
                                          "reproduced_alone": outcome.get("reproduced_alone")}
                        print(f"fuzz: FINDING {key}\n      {describe_case(case)}\n      "
                              f"replay: {prefix} --replay {path}", flush=True)
    finally:
        if worker is not None:
            worker.close()
    elapsed = time.monotonic() - start
    total = Counter()
    for counts in per_target.values():
        total.update(counts)
    summary = {
        "seed": args.seed, "only": args.only, "cases": index, "seconds": round(elapsed, 1),
        "build_dir": str(args.build_dir), "sanitized": sanitized(args.build_dir),
        "outcomes": dict(total), "worker_restarts": restarts,
        "per_target": {t: dict(c) for t, c in sorted(per_target.items())},
        "seconds_per_target": {t: round(s, 2) for t, s in sorted(seconds_per_target.items())},
        "slowest": [{"seconds": round(s, 2), "target": t, "index": i} for s, t, i in slowest],
        "findings": per_signature, "harness_errors": harness_errors[:20],
        "slow_budgets": slow_budgets[:20],
        "nonfinite_outputs": dict(nonfinite), "nonfinite_examples": nonfinite_examples,
        "known_findings": known_findings,
        "rerun": f"{prefix} --seed {args.seed}" + (f" --only {args.only}" if args.only else "")
                 + f" --cases {index}",
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=str) + "\n")
    print(f"fuzz: {index} cases in {elapsed:.0f} s: " +
          ", ".join(f"{k} {v}" for k, v in sorted(total.items())) + f"; {restarts} worker restarts")
    if nonfinite:
        print("fuzz: answers holding NaN/inf (not counted as findings; see summary.json): " +
              ", ".join(f"{t} {c}" for t, c in sorted(nonfinite.items())))
    for key, entry in known_findings.items():
        print(f"fuzz: known ({entry['count']}x, not failing): {key}\n        {entry['why']}")
    if harness_errors:
        print(f"fuzz: {len(harness_errors)} harness errors (the fuzzer's own specs), first: {harness_errors[0]}")
    if per_signature:
        print(f"fuzz: {len(per_signature)} distinct findings (seed {args.seed}; rerun: {summary['rerun']}):")
        for key, entry in per_signature.items():
            print(f"  {entry['count']:4d}x {key}\n        {entry['cases'][0] if entry['cases'] else ''}")
        return 1
    print(f"fuzz: no findings (seed {args.seed}); summary in {out / 'summary.json'}")
    return 2 if harness_errors and args.strict_harness else 0


def replay_one(args, path):
    with open(path, "rb") as f:
        data = pickle.load(f)
    case = data["case"] if "case" in data else data
    print(f"replay: {path}\n        {describe_case(case)}\n        notes: {'; '.join(case['notes'])}")
    if data.get("outcome"):
        before = data["outcome"]
        print(f"        recorded: {before['status']} {before.get('error', '')} {before.get('message', '')[:300]}")
    if args.in_process:  # for a debugger: the crash happens here
        import worker as worker_module
        module = worker_module.import_module(module_dir(args.build_dir))
        outcome = worker_module.run_case(case, module)
    else:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        log_path = out / "replay.log"
        log_path.write_bytes(b"")
        w = Worker(args.build_dir, log_path, args.memory_limit_mb)
        outcome = settle(case, w.run(case, args.call_timeout))
        w.close()
        if outcome.get("stderr"):
            print(outcome["stderr"][-6000:])
    print(f"replay: {outcome['status']} {outcome.get('error', '')} {outcome.get('reason', '')} {outcome.get('why', '')} "
          f"{outcome.get('message', '')[:1000]} ({outcome.get('seconds', 0):.2f} s)")
    return outcome["status"] in FINDING_STATUSES


def replay(args):
    """--replay FILE runs one case file; --replay FOLDER every *.pkl in it
    (tests/fuzz/findings: the past findings, which the gate replays). Exit 1
    when any is still a finding."""
    path = Path(args.replay)
    files = sorted(path.glob("*.pkl")) if path.is_dir() else [path]
    if not files:
        print(f"replay: no case files (*.pkl) in {path}", file=sys.stderr)
        return 2
    still = [f for f in files if replay_one(args, f)]
    if path.is_dir():
        print(f"replay: {len(files)} case files, {len(still)} still findings"
              + "".join(f"\n  {f}" for f in still))
    return 1 if still else 0


def parse(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seconds", type=float, default=60.0, help="time budget for new cases (default 60)")
    p.add_argument("--cases", type=int, default=None, help="stop after this many cases")
    p.add_argument("--seed", type=int, default=None, help="seed (default: from the clock, printed)")
    p.add_argument("--out", default="fuzz-out", help="output folder (summary.json, findings/)")
    p.add_argument("--only", default="", help="comma-separated targets (see --list)")
    p.add_argument("--replay", default=None,
                   help="run one saved case file again, alone, or every *.pkl in a folder")
    p.add_argument("--in-process", action="store_true", help="with --replay: call in this process (gdb)")
    p.add_argument("--build-dir", default=default_build_dir(),
                   help="build folder holding python/paramorph_native*.so (default $PARAMORPH_BUILD_DIR or build)")
    p.add_argument("--call-timeout", type=float, default=30.0, help="seconds one call may take (default 30)")
    p.add_argument("--memory-limit-mb", type=int, default=4096, help="worker address-space limit (0: none)")
    p.add_argument("--recycle", type=int, default=300, help="start a fresh worker after this many cases")
    p.add_argument("--keep-per-signature", type=int, default=3, help="case files kept per distinct finding")
    p.add_argument("--no-confirm", dest="confirm", action="store_false",
                   help="do not rerun a crashing case alone in a fresh worker")
    p.add_argument("--strict-harness", action="store_true", help="exit 2 when the fuzzer's own specs fail")
    p.add_argument("--list", action="store_true", help="print the targets and exit")
    args = p.parse_args(argv)
    if args.seed is None:
        args.seed = int(time.time()) % 1000003
    return args


def main(argv=None):
    args = parse(argv)
    if args.list:
        print("\n".join(sorted(cases.TABLE)))
        return 0
    if args.replay:
        return replay(args)
    return fuzz(args)


if __name__ == "__main__":
    sys.exit(main())
