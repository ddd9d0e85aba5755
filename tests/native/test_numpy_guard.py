"""A build whose pybind11 reads NumPy 2 arrays wrongly (before 2.12: int32
results came back as zeros, without an error) refuses to load under NumPy 2
with a sentence saying what to do, and loads under NumPy 1 (issue 30)."""
import subprocess
import sys

import numpy as np
import pytest

from conftest import BUILD


def import_with_numpy_version(version):
    code = (f"import sys; sys.path.insert(0, {str(BUILD)!r}); import numpy; numpy.__version__ = {version!r}; "
            "import paramorph_native; print(paramorph_native.__version__)")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)


@pytest.mark.skipif(int(np.__version__.split(".")[0]) >= 2, reason="this Python already has NumPy 2")
def test_numpy_2_is_refused_with_what_to_do_unless_the_build_reads_it():
    import paramorph_native as pm
    built = import_with_numpy_version("2.1.0")
    if built.returncode == 0:  # a build with pybind11 >= 2.12 reads NumPy 2: nothing to refuse
        return
    assert "ImportError" in built.stderr
    assert "NumPy 2.1.0" in built.stderr and "pybind11 >= 2.12" in built.stderr and "NumPy < 2" in built.stderr
    ones = import_with_numpy_version(np.__version__)
    assert ones.returncode == 0 and ones.stdout.strip() == pm.__version__
