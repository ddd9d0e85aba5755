"""devices(): what OpenCL offers, and why a device is rejected."""
import glob

import pytest

import meshes
import paramorph_native as pm


def test_devices_are_described():
    found = pm.devices()
    keys = {"platform", "name", "type", "version", "usable", "reason", "global_memory",
            "compute_units", "selected"}
    for d in found:
        assert keys <= set(d)
        assert d["usable"] == (d["reason"] == ""), d
    assert sum(d["selected"] for d in found) <= 1
    assert pm.opencl_available() == any(d["selected"] for d in found)
    if not pm.opencl_available():
        assert pm.opencl_error()


def test_pocl_gives_a_usable_device_when_installed():
    if not glob.glob("/etc/OpenCL/vendors/pocl.icd"):
        pytest.skip("PoCL is not installed")
    assert any(d["usable"] for d in pm.devices())


def test_with_no_opencl_driver_the_module_imports_runs_on_the_cpu_and_says_why(tmp_path):
    # The OpenCL loader (ocl-icd) finds no driver when its vendor folder is
    # empty: a minimal system or a container without a GPU looks like this.
    import os
    import subprocess
    import sys
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import numpy as np, paramorph_native as pm, meshes\n"
        "assert pm.devices() == [] and not pm.opencl_available(), pm.devices()\n"
        "V, F = meshes.noisy_blob(2)\n"
        "r = pm.sphere_map(V, F)\n"
        "assert r.flipped == 0 and r.backend == 'cpu', (r.flipped, r.backend)\n"
        "print(pm.opencl_error())\n")
    env = dict(os.environ, OCL_ICD_VENDORS=str(tmp_path), PYTHONPATH=os.path.dirname(pm.__file__))
    env.pop("PARAMORPH_OPENCL_DISABLE", None)
    here = os.path.dirname(os.path.abspath(__file__))
    proc = subprocess.run([sys.executable, "-c", code, here], env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "no OpenCL driver found" in proc.stdout and "CPU path" in proc.stdout, proc.stdout


def test_auto_takes_the_cpu_path_over_an_opencl_cpu_device():
    # PoCL runs the kernels on the same cores as the C++ path, slower
    # (compute/select_backend.h has the figures); auto picks OpenCL for GPUs only.
    devices = [d for d in pm.devices() if d["usable"]]
    if not devices or not any(d["selected"] for d in devices):
        pytest.skip("no usable OpenCL device")
    selected = next(d for d in devices if d["selected"])
    V, F = meshes.noisy_blob(2)
    auto = pm.sphere_map(V, F)
    if selected["type"] == "cpu":
        assert auto.backend == "cpu" and "is a CPU" in auto.backend_note, auto.backend_note
        assert pm.sphere_map(V, F, backend="opencl").backend == "opencl"  # still there when asked for
    else:
        assert auto.backend == "opencl"
