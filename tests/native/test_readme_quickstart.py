"""The README's Python quickstart (the block after the quickstart marker)
runs as written, on two meshes saved as OBJ files: what a researcher who
ran `pip install .` tries first."""
import os
import re
import subprocess
import sys
from pathlib import Path

import paramorph_native

import meshes

README = Path(__file__).resolve().parents[2] / "README.md"
MARKER = "<!-- quickstart: tests/native/test_readme_quickstart.py -->"


def quickstart():
    text = README.read_text(encoding="utf-8")
    assert MARKER in text, "the README lost its quickstart marker"
    return re.search(r"```python\n(.*?)```", text[text.index(MARKER):], re.S).group(1)


def save_obj(path, V, F):
    with open(path, "w") as f:
        f.writelines("v %.17g %.17g %.17g\n" % tuple(v) for v in V)
        f.writelines("f %d %d %d\n" % tuple(t + 1) for t in F)


def test_the_readme_quickstart_runs_and_prints_fold_free_results(tmp_path):
    save_obj(tmp_path / "blob.obj", *meshes.noisy_blob(3))
    save_obj(tmp_path / "octopus.obj", *meshes.coarse_octopus(3, limbs=4))
    (tmp_path / "quickstart.py").write_text(quickstart())
    # The module the tests import (a build folder or the installed wheel).
    env = dict(os.environ, PYTHONPATH=os.path.dirname(paramorph_native.__file__))
    proc = subprocess.run([sys.executable, "quickstart.py"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = proc.stdout
    assert "sphere map: 0 folded faces" in out
    assert re.search(r"isometric map: \(\d+, 2\) 0 folded faces", out), out
    assert int(re.search(r"morph: (\d+) merged faces", out).group(1)) > 1280
    assert int(re.search(r"paste: (\d+) vertices moved", out).group(1)) > 0
