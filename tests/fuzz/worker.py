"""The child process of the fuzz driver: imports paramorph_native, then reads
pickled cases from stdin and answers each with a pickled outcome on its own
stdout pipe (the module's and libraries' prints go to stderr), until stdin
closes. A case that kills the process (a signal, a sanitizer abort) or runs
past the driver's time limit is seen by the driver, not here.

Usage (by fuzz.py): worker.py MODULE_DIR [--memory-limit-mb N]
"""
import faulthandler
import os
import pickle
import struct
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import specs  # noqa: E402
from specs import FuzzCallbackError, has_callback, lookup, resolve  # noqa: E402

from cases import TYPED_ERRORS  # noqa: E402  (one list: the table's)


class SetupFailure(Exception):
    """A module call that builds an argument (a spec) failed."""

    def __init__(self, target, error):
        super().__init__(f"{target}: {type(error).__name__}: {error}")
        self.target, self.error = target, error


def classify(error, case, module):
    """'ok' (returned, or the callback's own exception came back), 'typed' (a refusal
    the API promises) or 'untyped' (a finding), with a reason for untyped ones."""
    if error is None or isinstance(error, FuzzCallbackError):
        return "ok", ""
    message = str(error)
    typed = tuple(getattr(module, name) for name in TYPED_ERRORS if hasattr(module, name))
    if isinstance(error, typed):
        return "typed", ""
    everything = (case["args"], case["kwargs"])
    if isinstance(error, module.Cancelled):
        if has_callback(everything, "false") or has_callback(everything, "after"):
            return "typed", ""
        return "untyped", "Cancelled without a callback asking to stop"
    device_error = getattr(module, "DeviceError", None)  # a stand-in module may lack it
    if device_error is not None and isinstance(error, device_error):
        return "typed", ""
    if isinstance(error, module.ComputeError):
        if device_error is None and ("OpenCL" in message or "kernels/" in message):
            return "typed", ""
        return "untyped", "ComputeError that is not an OpenCL failure (DeviceError)"
    if type(error) is TypeError:
        if "incompatible function arguments" in message or "incompatible constructor arguments" in message:
            return "typed", ""  # pybind11's argument conversion
        if has_callback(everything, "wrong_arity") and "positional argument" in message:
            return "ok", ""     # calling the callback itself failed: its exception came back
    return "untyped", f"{type(error).__module__}.{type(error).__name__}"


def _resolve_checked(value, module):
    """resolve(), with a failure of a module call tagged by its target."""
    if isinstance(value, specs.Call):
        args = tuple(_resolve_checked(a, module) for a in value.args)
        kwargs = {k: _resolve_checked(v, module) for k, v in value.kwargs.items()}
        try:
            return resolve(specs.Call(value.target, args, kwargs, value.attr, value.method), module)
        except Exception as error:  # noqa: BLE001 - reported, classified by the caller
            raise SetupFailure(value.target, error) from error
    if isinstance(value, specs.Apply):
        inner = _resolve_checked(value.value, module)
        params = tuple(_resolve_checked(p, module) for p in value.params)
        return resolve(specs.Apply(value.name, inner, *params), module)
    if isinstance(value, tuple):
        return tuple(_resolve_checked(v, module) for v in value)
    if isinstance(value, list):
        return [_resolve_checked(v, module) for v in value]
    if isinstance(value, dict):
        return {k: _resolve_checked(v, module) for k, v in value.items()}
    return resolve(value, module)


def run_case(case, module):
    """Resolves the case's arguments and calls its target; returns the outcome dict."""
    start = time.perf_counter()
    outcome = {"stage": "call"}
    try:
        args = _resolve_checked(case["args"], module)
        kwargs = _resolve_checked(case["kwargs"], module)
    except SetupFailure as failure:
        status, reason = classify(failure.error, case, module)
        outcome.update(stage=f"setup: {failure.target}", error=type(failure.error).__name__,
                       message=str(failure.error)[:2000],
                       status="setup_refused" if status != "untyped" else "untyped", reason=reason)
        outcome["seconds"] = time.perf_counter() - start
        return outcome
    except Exception as error:  # noqa: BLE001 - a fault of the fuzzer's own specs
        outcome.update(status="harness_error", error=type(error).__name__, message=str(error)[:2000])
        return outcome
    fn = lookup(module, case["target"])
    error = result = None
    try:
        result = fn(*args, **kwargs)
    except Exception as caught:  # noqa: BLE001 - classified below
        error = caught
    status, reason = classify(error, case, module)
    outcome.update(status=status, reason=reason, seconds=time.perf_counter() - start)
    if error is not None:
        outcome.update(error=type(error).__name__, message=str(error)[:2000])
    elif status == "ok":
        bad = nonfinite_fields(result)
        if bad:
            outcome["nonfinite"] = bad[:5]
    return outcome


def nonfinite_fields(value, name="result", depth=0):
    """Names of the float arrays and numbers in a result that hold NaN or inf:
    not a finding by itself (a distance may be inf by design), reported apart
    so a silent garbage answer shows."""
    import math

    import numpy as np
    out = []
    if isinstance(value, float):
        return [name] if not math.isfinite(value) else []
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc" and value.size and not np.isfinite(value).all():
            return [name]
        return []
    if depth >= 2:
        return []
    if isinstance(value, (list, tuple)):
        for k, item in enumerate(value[:50]):
            out += nonfinite_fields(item, f"{name}[{k}]", depth + 1)
    elif isinstance(value, dict):
        for key, item in list(value.items())[:50]:
            out += nonfinite_fields(item, f"{name}[{key!r}]", depth + 1)
    elif type(value).__module__ not in ("builtins", "numpy") and value is not None:
        for attr in dir(type(value)):
            if attr.startswith("_") or not isinstance(getattr(type(value), attr, None), property):
                continue
            try:
                item = getattr(value, attr)
            except Exception:  # noqa: BLE001 - a property that refuses is not ours to judge here
                continue
            out += nonfinite_fields(item, f"{name}.{attr}", depth + 1)
    return out


def import_module(module_dir):
    sys.path.insert(0, str(module_dir))
    name = os.environ.get("PARAMORPH_FUZZ_MODULE", "paramorph_native")
    return __import__(name)


def main():
    module_dir = sys.argv[1]
    if "--memory-limit-mb" in sys.argv:
        limit = int(sys.argv[sys.argv.index("--memory-limit-mb") + 1])
        if limit > 0:
            import resource
            resource.setrlimit(resource.RLIMIT_AS, (limit << 20, limit << 20))
    faulthandler.enable()
    channel = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)  # anything printed by the module goes to the log, not the channel
    sys.stdout = os.fdopen(1, "w", buffering=1)
    module = import_module(module_dir)
    stdin = sys.stdin.buffer
    while True:
        head = stdin.read(4)
        if len(head) < 4:
            return
        case = pickle.loads(stdin.read(struct.unpack("<I", head)[0]))
        print(f"=== case {case.get('seed')}/{case.get('index')} {case['target']}", file=sys.stderr, flush=True)
        outcome = run_case(case, module)
        data = pickle.dumps(outcome)
        channel.write(struct.pack("<I", len(data)) + data)
        channel.flush()


if __name__ == "__main__":
    main()
