"""Whether a build reads NumPy 2 arrays right is settled by the pybind11 it
was compiled with: before 2.12 (Debian 12's 2.10) int32 results came back as
zeros under NumPy 2, without an error, so such a build refuses to load under
NumPy 2 with a sentence saying what to do; a build with pybind11 >= 2.12
(PyPI's, for CPython 3.13 / Blender 5.x) loads under NumPy 1 and 2 and
answers right under both (issue 30)."""
import re
import subprocess
import sys

import numpy as np
import pytest

import meshes
import paramorph_native as pm
from conftest import BUILD

NUMPY_MAJOR = int(np.__version__.split(".")[0])


def built_with_pybind11():
    return tuple(int(part) for part in pm.build_info()["pybind11"].split(".")[:2])


def import_with_numpy_version(version):
    code = (f"import sys; sys.path.insert(0, {str(BUILD)!r}); import numpy; numpy.__version__ = {version!r}; "
            "import paramorph_native; print(paramorph_native.__version__)")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)


def test_build_info_names_the_pybind11_the_module_was_built_with():
    assert re.fullmatch(r"\d+\.\d+\.\w+", pm.build_info()["pybind11"])
    assert built_with_pybind11() >= (2, 10)  # the oldest this project builds with (Debian 12)


@pytest.mark.skipif(NUMPY_MAJOR >= 2, reason="the refusal is seen from NumPy 1, with NumPy 2's version shown to it")
def test_numpy_2_is_refused_with_what_to_do_exactly_when_the_build_cannot_read_it():
    built = import_with_numpy_version("2.1.0")
    if built_with_pybind11() >= (2, 12):
        assert built.returncode == 0 and built.stdout.strip() == pm.__version__, built.stderr
    else:
        assert built.returncode != 0 and "ImportError" in built.stderr
        assert "NumPy 2.1.0" in built.stderr and "pybind11 >= 2.12" in built.stderr and "NumPy < 2" in built.stderr
    ones = import_with_numpy_version(np.__version__)
    assert ones.returncode == 0 and ones.stdout.strip() == pm.__version__


def test_a_build_that_loaded_under_numpy_2_reads_it():
    if NUMPY_MAJOR >= 2:  # only a build with pybind11 >= 2.12 gets this far (conftest imported it)
        assert built_with_pybind11() >= (2, 12)
    # What went wrong silently before the guard (pybind11 2.10, NumPy 2.4; seen
    # again by importing past the guard): 1-D int32 results such as a morph's
    # vertex_of_a came back as zeros, while 2-D ones and validate's were right.
    VA, FA = meshes.icosphere(2)
    VB, FB = meshes.noisy_blob(2)
    m = pm.morph(VA, FA, VB, FB)
    vertex_of_a, vertex_of_b = np.asarray(m.vertex_of_a), np.asarray(m.vertex_of_b)
    assert vertex_of_a.dtype == np.int32 and vertex_of_a.shape == (len(VA),)
    np.testing.assert_allclose(np.asarray(m.source)[vertex_of_a], VA, atol=1e-12)
    np.testing.assert_allclose(np.asarray(m.target)[vertex_of_b], VB, atol=1e-12 * np.ptp(VB))
