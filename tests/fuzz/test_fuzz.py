"""The fuzz driver's own tests: its table covers every public callable of
paramorph_native (a new function without an entry fails here), its cases are
deterministic for a seed and pickle, and its worker tells a crash, a hang, an
untyped exception and a typed refusal apart (on a stand-in module whose
functions do exactly that)."""
import pickle
import sys
import textwrap

import numpy as np
import pytest

import cases
import fuzz
import paramorph_native as pm
import specs

HERE = fuzz.HERE


def test_table_covers_every_public_callable():
    public = cases.public_callables(pm)
    missing = sorted(public - set(cases.TABLE))
    stale = sorted(set(cases.TABLE) - public)
    assert not missing, f"public callables without a fuzz entry in tests/fuzz/cases.py TABLE: {missing}"
    assert not stale, f"fuzz entries for names the module no longer has: {stale}"


def test_every_class_is_listed_once():
    classes = {n for n in dir(pm) if not n.startswith("_") and isinstance(getattr(pm, n), type)}
    errors = {n for n in classes if issubclass(getattr(pm, n), BaseException)}
    assert errors == set(cases.TYPED_ERRORS) | set(cases.UNTYPED_ERRORS), \
        "exception classes must be listed in cases.TYPED_ERRORS or UNTYPED_ERRORS"
    others = classes - errors
    assert not set(cases.RESULT_TYPES) & set(cases.TABLE)
    assert others == {n for n in others if n in cases.RESULT_TYPES or n in cases.TABLE}, \
        f"classes neither fuzzed nor listed as result types: {sorted(others - set(cases.RESULT_TYPES) - set(cases.TABLE))}"
    assert set(cases.RESULT_TYPES) <= others, "RESULT_TYPES names classes the module does not have"


@pytest.mark.parametrize("name", cases.RESULT_TYPES)
def test_result_types_cannot_be_constructed(name):
    # What makes them result types: Python cannot build one, so there is no
    # constructor to fuzz (their methods are fuzzed through "Class.method").
    with pytest.raises(TypeError, match="No constructor defined"):
        getattr(pm, name)()


def test_typed_errors_are_mesh_errors():
    for name in cases.TYPED_ERRORS:
        assert issubclass(getattr(pm, name), pm.MeshError)
    for name in cases.UNTYPED_ERRORS:
        assert not issubclass(getattr(pm, name), pm.MeshError)


def test_only_a_device_error_is_a_valid_compute_error():
    # Issue 29: an OpenCL failure is a DeviceError; a plain ComputeError is a
    # finding even when its text mentions OpenCL (the class decides, not the words).
    import worker
    case = {"args": (), "kwargs": {}}
    assert worker.classify(pm.DeviceError("building kernels/sphere.cl failed"), case, pm) == ("typed", "")
    status, reason = worker.classify(pm.ComputeError("OpenCL error in clFinish (code -5)"), case, pm)
    assert status == "untyped" and "DeviceError" in reason
    assert worker.classify(pm.ComputeError("could not build a fold-free start"), case, pm)[0] == "untyped"


@pytest.mark.parametrize("target", sorted(cases.TABLE))
def test_cases_are_deterministic_and_pickle(target):
    for index in range(12):
        a = pickle.dumps(cases.make_case(5, index, target))
        b = pickle.dumps(cases.make_case(5, index, target))
        assert a == b
        assert pickle.loads(a)["target"] == target
    assert pickle.dumps(cases.make_case(5, 0, target)) != pickle.dumps(cases.make_case(6, 0, target)) \
        or target in ("build_info", "devices", "opencl_available", "opencl_error")


def test_schedule_reaches_every_target_each_round():
    schedule = cases.schedule(3, cases.TABLE)
    first = [next(schedule)[1] for _ in range(len(cases.TABLE))]
    assert sorted(first) == sorted(cases.TABLE)


def test_mutations_keep_shapes_where_they_promise():
    a = np.arange(12, dtype=np.float64).reshape(4, 3)
    strided = specs.MUTATIONS["strided"](a, 0.0)
    assert not strided.flags.c_contiguous and np.array_equal(strided, a)
    assert specs.MUTATIONS["fortran"](a, 0.0).flags.f_contiguous
    assert np.isnan(specs.MUTATIONS["nan"](a, 0.5)).sum() == 3
    assert specs.MUTATIONS["index_minus1"](a.astype(np.int32), 0.0).min() == -1


STAND_IN = textwrap.dedent("""
    import os, signal, time
    class MeshError(ValueError): pass
    class InvalidInputError(MeshError): pass
    class Cancelled(RuntimeError): pass
    class ComputeError(RuntimeError): pass
    def fine(*args, **kwargs): return 1
    def refuses(*args, **kwargs): raise InvalidInputError("bad V")
    def untyped(*args, **kwargs): raise RuntimeError("internal failure")
    def crashes(*args, **kwargs): os.kill(os.getpid(), signal.SIGSEGV)
    def hangs(*args, **kwargs): time.sleep(60)
    def cancels(*args, progress=None): progress(0.0, "start"); raise Cancelled("cancelled")
    def calls_back(*args, progress=None): progress(0.0, "start"); return 1
""")


@pytest.fixture()
def stand_in(tmp_path, monkeypatch):
    (tmp_path / "python").mkdir()
    (tmp_path / "python" / "stand_in_native.py").write_text(STAND_IN)
    monkeypatch.setenv("PARAMORPH_FUZZ_MODULE", "stand_in_native")
    return tmp_path


def _case(target, **kwargs):
    return {"seed": 0, "index": 0, "target": target, "args": (np.zeros((3, 3)),), "kwargs": kwargs,
            "notes": [], "p_mut": 0.0}


def test_worker_tells_outcomes_apart(stand_in):
    worker = fuzz.Worker(stand_in, stand_in / "worker.log", memory_limit_mb=0)
    try:
        assert worker.run(_case("fine"), 20)["status"] == "ok"
        assert worker.run(_case("refuses"), 20)["status"] == "typed"
        untyped = worker.run(_case("untyped"), 20)
        assert untyped["status"] == "untyped" and untyped["error"] == "RuntimeError"
        # Cancelled is a valid answer only when the callback asked to stop.
        assert worker.run(_case("cancels", progress=specs.Callback("false")), 20)["status"] == "typed"
        assert worker.run(_case("cancels", progress=specs.Callback("true")), 20)["status"] == "untyped"
        # The callback's own exception coming back is what the API promises.
        assert worker.run(_case("calls_back", progress=specs.Callback("raise")), 20)["status"] == "ok"
        crash = worker.run(_case("crashes"), 20)
        assert crash["status"] == "crash" and crash["error"] == "SIGSEGV"
        assert "case 0/0 crashes" in crash["stderr"]
    finally:
        worker.close()
    worker = fuzz.Worker(stand_in, stand_in / "worker.log", memory_limit_mb=0)
    try:
        assert worker.run(_case("hangs"), 1.0)["status"] == "timeout"
    finally:
        worker.close()


def test_findings_are_saved_and_replay(stand_in, tmp_path, capsys):
    case = _case("crashes")
    outcome = {"status": "crash", "error": "SIGSEGV", "seconds": 0.0}
    path = fuzz.save_finding(tmp_path / "out", 1, case, outcome, "fuzz.py")
    assert path.exists() and path.with_suffix(".txt").exists()
    assert fuzz.main(["--replay", str(path), "--build-dir", str(stand_in), "--out", str(tmp_path / "r")]) == 1
    assert "replay: crash SIGSEGV" in capsys.readouterr().out


def test_a_folder_of_case_files_replays_each_and_fails_on_any(stand_in, tmp_path, capsys):
    folder = tmp_path / "findings"
    fine = fuzz.save_finding(tmp_path / "a", 1, _case("fine"), {"status": "untyped"}, "fuzz.py")
    crash = fuzz.save_finding(tmp_path / "b", 1, _case("crashes"), {"status": "crash"}, "fuzz.py")
    folder.mkdir()
    (folder / "1-fine.pkl").write_bytes(fine.read_bytes())
    args = ["--replay", str(folder), "--build-dir", str(stand_in), "--out", str(tmp_path / "r")]
    assert fuzz.main(args) == 0
    assert "1 case files, 0 still findings" in capsys.readouterr().out
    (folder / "2-crash.pkl").write_bytes(crash.read_bytes())
    assert fuzz.main(args) == 1
    assert "2 case files, 1 still findings" in capsys.readouterr().out
    assert fuzz.main(["--replay", str(tmp_path / "r"), "--build-dir", str(stand_in)]) == 2  # no case files


def test_the_committed_findings_are_case_files():
    files = sorted((HERE / "findings").glob("*.pkl"))
    assert files, "tests/fuzz/findings holds the past findings the gate replays"
    for path in files:
        with open(path, "rb") as f:
            data = pickle.load(f)
        assert data["case"]["target"] in cases.TABLE, path


def test_a_short_run_of_validate_has_no_findings(tmp_path):
    # validate() answers any array pair with a report or InvalidInputError.
    code = fuzz.main(["--only", "validate", "--cases", "60", "--seed", "11", "--out", str(tmp_path)])
    summary = (tmp_path / "summary.json").read_text()
    assert code == 0, summary
    assert '"cases": 60' in summary


def test_known_findings_name_real_targets_and_errors(monkeypatch):
    for target, error, pattern, why in cases.KNOWN_FINDINGS:
        assert target in cases.TABLE and why
        assert error in ("RuntimeError", "MemoryError", "IndexError", "ValueError", "TypeError", "SIGSEGV",
                         "SIGABRT", "SIGFPE", "")
    # The matching itself, on an entry made up for the test.
    entry = ("PasteSession.update", "RuntimeError", r"^Unable to cast", "a made-up entry")
    monkeypatch.setattr(cases, "KNOWN_FINDINGS", (entry,))
    case = {"target": "PasteSession.update"}
    assert fuzz.known(case, {"error": "RuntimeError", "message": "Unable to cast Python instance to C++ type"})
    assert not fuzz.known(case, {"error": "RuntimeError", "message": "something else"})
