"""devices(): what OpenCL offers, and why a device is rejected."""
import glob

import pytest

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
