"""DeviceError (issue 29): an OpenCL device that fails raises DeviceError, a
ComputeError, so `except ComputeError` still catches it (a computation that
cannot finish on any backend stays a plain ComputeError)."""
import os
import subprocess
import sys
import textwrap

import pytest

import paramorph_native as pm

HERE = os.path.dirname(os.path.abspath(__file__))


def test_device_error_is_a_compute_error_and_not_a_mesh_error():
    assert issubclass(pm.DeviceError, pm.ComputeError)
    assert issubclass(pm.ComputeError, RuntimeError)
    assert not issubclass(pm.DeviceError, pm.MeshError)
    assert not issubclass(pm.ComputeError, pm.DeviceError)
    assert pm.DeviceError.__module__ == pm.ComputeError.__module__ == "paramorph_native"
    with pytest.raises(pm.ComputeError, match="lost the device"):  # old handlers still catch it
        raise pm.DeviceError("lost the device")


def run_isolated(code, **env):
    """Runs `code` in a fresh interpreter (the OpenCL device is chosen once per
    process) with the test folder and the module on sys.path; its stdout."""
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join([os.path.dirname(pm.__file__), HERE]))
    for name in ("PARAMORPH_OPENCL_DISABLE", "PARAMORPH_OPENCL_DEVICE", "PARAMORPH_KERNEL_DIR"):
        environment.pop(name, None)
    environment.update(env)
    proc = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], env=environment,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout


# Prints the class of what each call raised and its message, on one line.
RAISED = """
    import numpy as np, paramorph_native as pm, meshes
    def raised(call):
        try:
            call()
        except Exception as error:  # noqa: BLE001 - the class is the point
            print(type(error).__name__, "|", " / ".join(str(error).splitlines()))
        else:
            print("returned")
"""


def test_opencl_requested_without_a_device_raises_device_error():
    out = run_isolated(RAISED + """
    V, F = meshes.noisy_blob(2)
    raised(lambda: pm.sphere_map(V, F, backend="opencl"))
    D, G = meshes.open_disc()
    raised(lambda: pm.isometric_map(D, G, backend="opencl"))
    print("cpu", pm.sphere_map(V, F, backend="cpu").flipped)  # the advice works
    """, PARAMORPH_OPENCL_DISABLE="1")
    lines = out.splitlines()
    for line in lines[:2]:
        assert line.startswith("DeviceError | backend=\"opencl\" requested but unavailable"), out
        assert "PARAMORPH_OPENCL_DISABLE" in line, out
    assert lines[2] == "cpu 0", out


def test_a_kernel_that_does_not_build_raises_device_error_with_the_build_log(tmp_path):
    if not any(d["usable"] for d in pm.devices()):
        pytest.skip("no usable OpenCL device")
    (tmp_path / "sphere.cl").write_text("__kernel void k(__global int* x) { x[0] = undefined_name; }\n")
    out = run_isolated(RAISED + """
    V, F = meshes.noisy_blob(2)
    raised(lambda: pm.sphere_map(V, F, backend="opencl"))
    r = pm.sphere_map(V, F)  # auto does not raise: the C++ path runs
    print("auto", r.backend, r.flipped)
    """, PARAMORPH_KERNEL_DIR=str(tmp_path))
    lines = out.splitlines()
    assert lines[0].startswith("DeviceError | backend=\"opencl\" requested but unavailable: building "
                               "kernels/sphere.cl failed"), out
    assert "undefined_name" in out, out  # the device's build log
    assert lines[-1] == "auto cpu 0", out

