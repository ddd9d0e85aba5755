"""The demo, run inside `blender -b` by scripts/demo.sh: sphere-maps a generated
blob and the closed-Suzanne sample scene, and saves each as a .blend with a
"Sphere" UV layer and a "Sphere" shape key."""
import argparse
import os
import sys

import bpy

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")
for path in (BUILD, os.path.join(REPO, "addon"), os.path.join(REPO, "blend_samples")):
    sys.path.insert(0, path)

import make_samples  # noqa: E402
from paramorph import bridge  # noqa: E402


def run(builder, filename, out_dir):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = builder()
    pm = bridge.require_native()
    V, F, _, _ = bridge.mesh_arrays(obj.data)
    report = pm.validate(V, F)
    if not report.is_closed_genus0:
        raise RuntimeError(f"{obj.name} is not a closed genus-0 mesh: {report}")
    result = bridge.sphere_map_object(obj)
    path = os.path.join(out_dir, filename)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    print(f"{obj.name}: V={V.shape[0]} F={F.shape[0]} flipped={result.flipped} "
          f"residual={result.residual:.2e} outer={result.outer_iterations} "
          f"inner={result.inner_iterations} seconds={result.seconds:.3f} "
          f"backend={result.backend} ({result.device})")
    print(f"wrote {path}")
    if result.flipped:
        raise RuntimeError(f"{obj.name}: {result.flipped} folded faces")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=os.path.join(REPO, "out"))
    out_dir = os.path.abspath(parser.parse_args(argv).out)
    os.makedirs(out_dir, exist_ok=True)
    run(lambda: make_samples.build_blob(subdivisions=6), "sphere_generated.blend", out_dir)
    run(make_samples.build_suzanne_closed, "sphere_suzanne.blend", out_dir)


main()
