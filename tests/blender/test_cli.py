"""The batch CLI (addon/paramorph/cli.py) as users run it: an installed copy
of the add-on (its Python files and the compiled module in one folder), its
cli.py run in a fresh Blender with `-- COMMAND IN OUT [options]`
(blender_subprocess.py says how under blender -b and under the PyPI bpy
module), on small sample inputs written here; then the output file is
opened and checked."""
import glob
import os
import shutil

import bpy
import numpy as np
import pytest

import blender_subprocess
import make_samples
from paramorph import bridge, uv_patch
from paramorph import cli as paramorph_cli

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")
ADDON = os.path.join(REPO, "addon", "paramorph")


pytestmark = pytest.mark.usefixtures("empty_scene")


@pytest.fixture(scope="module")
def cli(tmp_path_factory):
    """cli.py of an installed copy of the add-on, laid out as install-addon.sh does."""
    modules = glob.glob(os.path.join(BUILD, "paramorph_native*.so"))
    assert modules, f"no paramorph_native in {BUILD}: build it first"
    dest = tmp_path_factory.mktemp("addons") / "paramorph"
    shutil.copytree(ADDON, dest, ignore=shutil.ignore_patterns(
        "__pycache__", "*.pyc", "blender_manifest.toml", "paramorph_native*.so"))
    for module in modules:
        shutil.copy2(module, dest)
    return dest / "cli.py"


def run_cli(cli, tmp_path, *args):
    return blender_subprocess.run(cli, args, tmp_path)


def output(proc):
    return f"exit {proc.returncode}\n--- stdout\n{proc.stdout[-3000:]}\n--- stderr\n{proc.stderr[-3000:]}"


def save_blend(path):
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)


def export(path):
    """Writes every mesh of the scene to .obj, .ply or .stl (positions only)."""
    path = str(path)
    ext = os.path.splitext(path)[1]
    if ext == ".obj":
        bpy.ops.wm.obj_export(filepath=path, export_uv=False, export_materials=False)
    elif ext == ".ply":
        if "ply_export" in dir(bpy.ops.wm):
            bpy.ops.wm.ply_export(filepath=path, export_uv=False, export_normals=False,
                                  export_colors="NONE")
        else:
            bpy.ops.export_mesh.ply(filepath=path, use_uv_coords=False, use_normals=False,
                                    use_colors=False)
    elif ext == ".stl":
        if "stl_export" in dir(bpy.ops.wm):
            bpy.ops.wm.stl_export(filepath=path)
        else:
            bpy.ops.export_mesh.stl(filepath=path)


def open_output(path):
    assert os.path.isfile(path), path
    bpy.ops.wm.open_mainfile(filepath=str(path))


def uv_array(mesh, layer):
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2)


def face_labels(mesh):
    attribute = mesh.attributes.get("paramorph_region")
    assert attribute is not None and attribute.domain == "FACE" and attribute.data_type == "INT"
    labels = np.empty(len(mesh.polygons), dtype=np.int32)
    attribute.data.foreach_get("value", labels)
    return labels


def test_sphere_obj_in_blend_out(cli, tmp_path):
    vertices = len(make_samples.build_blob(subdivisions=3).data.vertices)
    src, out = tmp_path / "blob.obj", tmp_path / "out" / "blob_sphere.blend"
    export(src)
    proc = run_cli(cli, tmp_path, "sphere", src, out, "--weights", "barycentric", "--backend", "cpu")
    assert proc.returncode == 0, output(proc)
    assert "paramorph sphere: Blob: UV layer 'Sphere' and shape key 'Sphere'" in proc.stdout
    assert "on cpu" in proc.stdout, output(proc)  # the operator's report: --backend took effect
    assert f"wrote {out}" in proc.stdout

    open_output(out)
    mesh = bpy.data.objects["Blob"].data
    assert len(mesh.vertices) == vertices
    uv = uv_array(mesh, mesh.uv_layers["Sphere"])
    assert np.all(np.isfinite(uv)) and uv[:, 1].min() >= 0.0 and uv[:, 1].max() <= 1.0
    assert np.ptp(uv[:, 0]) > 0.9 and np.ptp(uv[:, 1]) > 0.8  # it covers the sphere
    key = mesh.shape_keys.key_blocks["Sphere"]
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    key.data.foreach_get("co", co)
    V = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", V)
    V = V.reshape(-1, 3)
    # The sphere around the mesh's bounding-box centre, through its farthest vertex.
    center = 0.5 * (V.min(axis=0) + V.max(axis=0))
    radii = np.linalg.norm(co.reshape(-1, 3) - center, axis=1)
    np.testing.assert_allclose(radii, np.linalg.norm(V - center, axis=1).max(), rtol=1e-5)


def test_sphere_obj_out_carries_the_sphere_uvs(cli, tmp_path):
    make_samples.build_blob(name="Ball", subdivisions=2)
    src = tmp_path / "ball.blend"
    save_blend(src)
    as_blend, as_obj = tmp_path / "ball_sphere.blend", tmp_path / "ball_sphere.obj"
    for out in (as_blend, as_obj):
        proc = run_cli(cli, tmp_path, "sphere", src, out, "--no-shape-key", "--backend", "cpu")
        assert proc.returncode == 0, output(proc)
    assert not list(tmp_path.glob(".*paramorph-*"))  # the .obj was written through a temporary file
    assert "UV layer 'Sphere' (" in proc.stdout  # no shape key in the summary

    open_output(as_blend)
    mesh = bpy.data.objects["Ball"].data
    assert mesh.shape_keys is None
    expected = uv_array(mesh, mesh.uv_layers["Sphere"])
    assert mesh.uv_layers[0].name == "UVMap"  # the icosphere's own UVs stay

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=str(as_obj))
    imported = bpy.context.selected_objects[0].data
    assert len(imported.loops) == len(expected)
    # The .obj holds the Sphere UVs (not the icosphere's UVMap), to its 6 digits.
    np.testing.assert_allclose(uv_array(imported, imported.uv_layers.active), expected, atol=2e-5)


def test_sphere_on_an_open_mesh_fails_in_plain_words_and_writes_nothing(cli, tmp_path):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=6, y_subdivisions=6)
    src, out = tmp_path / "grid.obj", tmp_path / "grid_sphere.blend"
    export(src)
    proc = run_cli(cli, tmp_path, "sphere", src, out, "--no-repair")
    assert proc.returncode == 1, output(proc)
    assert ("paramorph sphere: error: Grid: mesh has 1 hole: close them (Fill Holes) first, or turn on Repair"
            in proc.stderr), output(proc)
    assert "wrote" not in proc.stdout
    assert not out.exists()


def test_sphere_repairs_a_messy_obj_and_fails_plainly_on_a_handle(cli, tmp_path):
    from test_repair import messy_sphere
    messy_sphere()
    src, out = tmp_path / "messy.obj", tmp_path / "messy_sphere.obj"
    export(src)
    proc = run_cli(cli, tmp_path, "sphere", src, out)
    assert proc.returncode == 0, output(proc)
    assert "repaired: merged" in proc.stdout and "filled" in proc.stdout, output(proc)
    assert out.exists()
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_torus_add()
    src, out = tmp_path / "torus.obj", tmp_path / "torus_sphere.obj"
    export(src)
    proc = run_cli(cli, tmp_path, "sphere", src, out)
    assert proc.returncode == 1 and "cannot remove handles" in proc.stderr, output(proc)
    assert not out.exists()


def test_an_opencl_device_that_fails_is_reported_as_the_device_with_the_cpu_way_out(cli, tmp_path, monkeypatch):
    # Issue 29: only a DeviceError blames the device (and names --backend cpu).
    make_samples.build_blob(subdivisions=2)
    src, out = tmp_path / "blob.obj", tmp_path / "blob_sphere.blend"
    export(src)
    monkeypatch.setenv("PARAMORPH_OPENCL_DISABLE", "1")  # the fresh Blender finds no device
    proc = run_cli(cli, tmp_path, "sphere", src, out, "--backend", "opencl")
    assert proc.returncode == 1, output(proc)
    assert ('paramorph sphere: error: Blob: the OpenCL device failed (backend="opencl" requested but '
            "unavailable: no usable OpenCL device (OpenCL disabled by PARAMORPH_OPENCL_DISABLE=1)): "
            "choose the CPU backend in the add-on preferences (--backend cpu on the command line)"
            in proc.stderr), output(proc)
    assert not out.exists()
    proc = run_cli(cli, tmp_path, "sphere", src, out, "--backend", "cpu")  # the advice works
    assert proc.returncode == 0 and out.exists(), output(proc)


def test_morph_pins_that_cannot_be_met_are_reported_as_pins_not_uvs(cli, tmp_path):
    # Issue 29: the morph's ConstraintError names the pins; the advice is about them.
    V = bridge.mesh_arrays(make_samples.build_blob(subdivisions=2).data)[0]
    a, b, c = (int(np.argmax(V[:, axis])) for axis in range(3))
    blob_obj = tmp_path / "blob.obj"
    export(blob_obj)
    out = tmp_path / "morph.blend"
    proc = run_cli(cli, tmp_path, "morph", blob_obj, blob_obj, "--no-automatic", "-o", out,
                   "--pin", a, a, "--pin", b, c, "--pin", c, b)  # two swapped: a mirrored triple
    assert proc.returncode == 1, output(proc)
    assert "the pins are in mirrored order" in proc.stderr and "(pins 0, 1, 2)" in proc.stderr, output(proc)
    assert "move or remove the pins or pairs it names" in proc.stderr, output(proc)
    assert "UV" not in proc.stderr and "OpenCL" not in proc.stderr, output(proc)
    assert not out.exists()


def test_segment_extremities_stl_in(cli, tmp_path):
    vertices = len(make_samples.build_octopus(subdivisions=4, limbs=6).data.vertices)
    src, out = tmp_path / "octopus.stl", tmp_path / "octopus_regions.blend"
    export(src)
    proc = run_cli(cli, tmp_path, "segment", src, out, "--threshold", "1.5", "--min-area", "0.01")
    assert proc.returncode == 0, output(proc)

    open_output(out)
    (obj,) = [o for o in bpy.data.objects if o.type == "MESH"]
    mesh = obj.data
    assert len(mesh.vertices) == vertices  # the STL's corners were welded back
    labels = face_labels(mesh)
    count = int(labels.max()) + 1
    assert count >= 7  # six tentacles and the body
    assert np.array_equal(np.unique(labels), np.arange(count))
    assert f"{obj.name}: {count} regions in face attribute 'paramorph_region'" in proc.stdout
    color = mesh.attributes.get("paramorph_region_color")
    assert color is not None and color.domain == "CORNER"
    assert mesh.color_attributes.active_color.name == "paramorph_region_color"


def test_segment_features_ply_in_one_named_object(cli, tmp_path):
    make_samples.build_cad_part()
    src = tmp_path / "cad.ply"
    export(src)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    make_samples.build_cad_part()
    make_samples.build_blob(subdivisions=2)
    two = tmp_path / "two.blend"
    save_blend(two)

    out = tmp_path / "cad_regions.blend"
    proc = run_cli(cli, tmp_path, "segment", src, out, "--mode", "features",
                   "--normal-angle", "40", "--concavity-threshold", "0.02")
    assert proc.returncode == 0, output(proc)
    open_output(out)
    (obj,) = [o for o in bpy.data.objects if o.type == "MESH"]
    assert int(face_labels(obj.data).max()) + 1 >= 10  # sides, tops, bosses, ribs
    points = np.empty(len(obj.data.vertices), dtype=np.int32)
    obj.data.attributes["paramorph_feature_point"].data.foreach_get("value", points)
    assert (points != 0).any() and set(np.unique(points)) <= {-1, 0, 1}

    # --object: only the named mesh of a .blend is segmented.
    bpy.ops.wm.read_factory_settings(use_empty=True)
    out = tmp_path / "two_regions.blend"
    proc = run_cli(cli, tmp_path, "segment", two, out, "--mode", "features", "--object", "CadPart")
    assert proc.returncode == 0, output(proc)
    assert "paramorph segment: CadPart:" in proc.stdout and "Blob:" not in proc.stdout
    open_output(out)
    assert "paramorph_region" in bpy.data.objects["CadPart"].data.attributes
    assert "paramorph_region" not in bpy.data.objects["Blob"].data.attributes


def test_unwrap_keeps_pins_and_folds_nothing(cli, tmp_path):
    obj = make_samples.build_pinned_disc()
    mesh = obj.data
    before = uv_array(mesh, mesh.uv_layers.active)
    pins = uv_patch.uv_pins(mesh, mesh.uv_layers.active)
    assert pins.sum() >= 4
    src, out = tmp_path / "disc.blend", tmp_path / "disc_unwrapped.blend"
    save_blend(src)

    proc = run_cli(cli, tmp_path, "unwrap", src, out, "--max-iterations", "300", "--pins", "exact")
    assert proc.returncode == 0, output(proc)
    assert "paramorph unwrap: PinnedDisc: UV layer 'UVMap'" in proc.stdout
    open_output(out)
    obj = bpy.data.objects["PinnedDisc"]
    assert obj.mode == "OBJECT"
    mesh = obj.data
    after = uv_array(mesh, mesh.uv_layers.active)
    np.testing.assert_allclose(after[pins], before[pins], atol=1e-6)  # pins are hard
    assert np.abs(after - before).max() > 1e-3  # the free UVs moved
    # No folds: every UV triangle keeps the orientation of the start.
    mesh.calc_loop_triangles()
    tris = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", tris)
    a, b, c = (after[tris.reshape(-1, 3)[:, k]] for k in range(3))
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    a0, b0, c0 = (before[tris.reshape(-1, 3)[:, k]] for k in range(3))
    area0 = (b0[:, 0] - a0[:, 0]) * (c0[:, 1] - a0[:, 1]) - (b0[:, 1] - a0[:, 1]) * (c0[:, 0] - a0[:, 0])
    assert np.all(np.sign(area) == np.sign(area0)) and np.all(np.abs(area) > 0)


@pytest.mark.parametrize("args, code, message", [
    (["bogus", "a.obj", "b.blend"], 2, "invalid choice: 'bogus'"),
    (["sphere", "a.obj"], 2, "the following arguments are required: OUT"),
    (["sphere", "a.obj", "b.stl"], 2, "OUT must end in .blend, .obj, .ply"),
    (["segment", "a.obj", "b.blend", "--mode", "features", "--threshold", "2"], 2,
     "--threshold applies to --mode extremities"),
    (["sphere", "missing.obj", "b.blend"], 1, "missing.obj: no such file"),
])
def test_usage_and_input_errors(cli, tmp_path, args, code, message):
    proc = run_cli(cli, tmp_path, *[str(tmp_path / a) if "." in a else a for a in args])
    assert proc.returncode == code, output(proc)
    assert message in proc.stderr, output(proc)
    if code == 2:
        assert "usage: " in proc.stderr
    assert not (tmp_path / "b.blend").exists()


def test_option_out_of_range_and_unknown_object(cli, tmp_path):
    make_samples.build_blob(subdivisions=1)
    src = tmp_path / "blob.blend"
    save_blend(src)
    proc = run_cli(cli, tmp_path, "segment", src, tmp_path / "x.blend", "--threshold", "0.01")
    assert proc.returncode == 2 and "--threshold 0.01 is below its minimum 0.05" in proc.stderr, \
        output(proc)
    proc = run_cli(cli, tmp_path, "sphere", src, tmp_path / "x.blend", "--object", "Nope")
    assert proc.returncode == 1, output(proc)
    assert "no object named 'Nope' (mesh objects: Blob)" in proc.stderr
    assert not (tmp_path / "x.blend").exists()


def test_morph_two_obj_files_into_an_animated_blend(cli, tmp_path):
    blob = make_samples.build_blob(subdivisions=3)
    blob_tip = int(np.argmax(bridge.mesh_arrays(blob.data)[0][:, 0]))
    blob_obj = tmp_path / "blob.obj"
    export(blob_obj)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    octopus = make_samples.build_octopus(subdivisions=3, limbs=4)
    octopus_tip = int(np.argmax(bridge.mesh_arrays(octopus.data)[0][:, 0]))
    octopus_obj = tmp_path / "octopus.obj"
    export(octopus_obj)
    out = tmp_path / "out" / "morph.blend"
    proc = run_cli(cli, tmp_path, "morph", blob_obj, octopus_obj, "--topology", "merged", "--frames", "12", "--start", "5",
                   "--in-betweens", "1", "--pin", str(blob_tip), str(octopus_tip), "-o", out)
    assert proc.returncode == 0, output(proc)
    assert "paramorph morph: Blob to Octopus:" in proc.stdout and f"wrote {out}" in proc.stdout
    # The chosen candidate and what held exactly, in one line.
    assert "paramorph morph: chosen " in proc.stdout and ", score " in proc.stdout, output(proc)
    assert "1 pin and " in proc.stdout and " held exactly" in proc.stdout, output(proc)

    open_output(out)
    scene = bpy.context.scene
    assert (scene.frame_start, scene.frame_end) == (5, 16)
    morph = bpy.data.objects["Blob to Octopus"]
    keys = morph.data.shape_keys
    assert [k.name for k in keys.key_blocks] == ["Basis", "Octopus 50%", "Octopus"]
    scene.frame_set(16)
    assert keys.key_blocks["Octopus"].value == pytest.approx(1.0)
    scene.frame_set(5)
    assert keys.key_blocks["Octopus"].value == pytest.approx(0.0)
    # The pin held: the merged vertex at the blob's tip ends exactly on the octopus's.
    A = bridge.mesh_arrays(bpy.data.objects["Blob"].data)[0]
    B = bridge.mesh_arrays(bpy.data.objects["Octopus"].data)[0]
    basis, end = (np.array([tuple(v.co) for v in keys.key_blocks[name].data]) for name in ("Basis", "Octopus"))
    merged = int(np.argmin(np.linalg.norm(basis - A[blob_tip], axis=1)))
    size = np.linalg.norm(np.ptp(B, axis=0))
    assert np.linalg.norm(basis[merged] - A[blob_tip]) <= 1e-6 * size
    assert np.linalg.norm(end[merged] - B[octopus_tip]) <= 1e-6 * size


def test_morph_usage_and_input_errors(cli, tmp_path):
    make_samples.build_blob(subdivisions=2)
    blob_obj = tmp_path / "blob.obj"
    export(blob_obj)
    proc = run_cli(cli, tmp_path, "morph", blob_obj, blob_obj, "-o", tmp_path / "out.obj")
    assert proc.returncode == 2 and "OUT must end in .blend" in proc.stderr, output(proc)
    proc = run_cli(cli, tmp_path, "morph", blob_obj, tmp_path / "missing.obj", "-o", tmp_path / "out.blend")
    assert proc.returncode == 1 and "B: " in proc.stderr and "no such file" in proc.stderr, output(proc)
    # Pins: a vertex pinned twice and a negative index are usage errors; an index past
    # the mesh's end is reported by object; --no-features is gone (--no-automatic).
    proc = run_cli(cli, tmp_path, "morph", blob_obj, blob_obj, "-o", tmp_path / "out.blend",
                   "--pin", "1", "2", "--pin", "1", "3")
    assert proc.returncode == 2 and "--pin 1 2 and --pin 1 3 both pin vertex 1 of A" in proc.stderr, output(proc)
    proc = run_cli(cli, tmp_path, "morph", blob_obj, blob_obj, "-o", tmp_path / "out.blend", "--pin", "-1", "2")
    assert proc.returncode == 2 and "vertex indices start at 0" in proc.stderr, output(proc)
    proc = run_cli(cli, tmp_path, "morph", blob_obj, blob_obj, "-o", tmp_path / "out.blend",
                   "--pin", "0", "99999", "--no-automatic")
    assert proc.returncode == 1 and "has no vertex 99999" in proc.stderr, output(proc)
    proc = run_cli(cli, tmp_path, "morph", blob_obj, blob_obj, "-o", tmp_path / "out.blend", "--no-features")
    assert proc.returncode == 2 and "--no-features" in proc.stderr, output(proc)
    assert not (tmp_path / "out.blend").exists()


def paste_inputs(tmp_path):
    """The paste sample saved as one .blend; returns its path."""
    make_samples.build_paste_pair()
    src = tmp_path / "pair.blend"
    save_blend(src)
    return src


def test_paste_copies_the_boss_and_pastes_it_onto_the_target(cli, tmp_path):
    if not hasattr(bridge.require_native(), "PasteSession"):
        pytest.skip("this build has no PasteSession")
    src = paste_inputs(tmp_path)
    out = tmp_path / "out" / "pasted.blend"
    x, y, z, r = make_samples.BOSS_BALL
    proc = run_cli(cli, tmp_path, "paste", src, src, out, "--source-object", "BossPlate",
                   "--target-object", "CurvedTarget", "--select-ball", f"{x},{y},{z},{r}",
                   "--at", "0,0,2", "--rotation", "30", "--scale", "0.8", "--backend", "cpu")
    assert proc.returncode == 0, output(proc)
    assert "paramorph paste: BossPlate: copied the feature of" in proc.stdout, output(proc)
    assert "paramorph paste: CurvedTarget: 5120 -> " in proc.stdout and f"wrote {out}" in proc.stdout
    open_output(out)
    mesh = bpy.data.objects["CurvedTarget"].data
    assert len(mesh.polygons) > 5120
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    assert co.reshape(-1, 3)[:, 2].max() > 1.3 + 0.15  # the boss on the top
    assert any(m.name == "Feature BossPlate" and m.use_fake_user for m in bpy.data.meshes)


def test_paste_errors_exit_1_and_usage_errors_exit_2(cli, tmp_path):
    src = paste_inputs(tmp_path)
    out = tmp_path / "never.blend"
    common = [src, src, out, "--source-object", "BossPlate", "--target-object", "CurvedTarget"]
    proc = run_cli(cli, tmp_path, "paste", *common, "--select-group", "Boss", "--at", "0,0,2")
    assert proc.returncode == 1, output(proc)
    assert "paramorph paste: error: BossPlate has no vertex group 'Boss' (groups: none)" in proc.stderr
    proc = run_cli(cli, tmp_path, "paste", *common, "--select-ball", "5,5,5,0.1", "--at", "0,0,2")
    assert proc.returncode == 1, output(proc)
    assert "paramorph paste: error: BossPlate: no faces selected" in proc.stderr, output(proc)
    proc = run_cli(cli, tmp_path, "paste", src, src, out, "--source-object", "Nope",
                   "--target-object", "CurvedTarget", "--select-ball", "0,0,0,1", "--at", "0,0,2")
    assert proc.returncode == 1 and "SOURCE has no mesh object named 'Nope'" in proc.stderr, output(proc)
    assert not out.exists()
    for bad in (["--select-ball", "1,2", "--at", "0,0,2"],                      # not 4 numbers
                ["--select-ball", "0,0,0,1"],                                # no --at
                ["--select-ball", "0,0,0,1", "--select-group", "G", "--at", "0,0,2"],  # both
                ["--select-ball", "0,0,0,1", "--at", "0,0,2", "--scale", "0"],  # out of range
                ["--select-ball", "0,0,0,1", "--at", "0,0,2", "--subdivision-level", "9"]):
        proc = run_cli(cli, tmp_path, "paste", *common, *bad)
        assert proc.returncode == 2, (bad, output(proc))
        assert "usage:" in proc.stderr, (bad, output(proc))
    assert not out.exists()


# --- OUT and IN paths: checked before any work, refused in plain words ---------

def snapshot(folder):
    """Every path under `folder`, with the bytes of each file (None for a folder)."""
    return {str(p.relative_to(folder)): p.read_bytes() if p.is_file() else None
            for p in sorted(folder.rglob("*"))}


def refused(proc, code, message):
    """Exit status `code`, `message` on stderr, no traceback, nothing written."""
    assert proc.returncode == code, output(proc)
    assert message in proc.stderr, output(proc)
    assert "Traceback" not in proc.stderr and "wrote" not in proc.stdout, output(proc)
    if code == 2:
        assert "usage: " in proc.stderr, output(proc)


def blob_files(tmp_path):
    """A folder "files" with the blob as blob.blend and blob.obj; returns the folder."""
    files = tmp_path / "files"
    files.mkdir()
    make_samples.build_blob(subdivisions=1)
    save_blend(files / "blob.blend")
    export(files / "blob.obj")
    return files


@pytest.mark.parametrize("ext", [".obj", ".ply", ".blend"])
def test_output_in_a_place_that_takes_no_file_fails_before_any_work(cli, tmp_path, ext):
    files = blob_files(tmp_path)
    notes = files / "notes.txt"
    notes.write_text("a file, not a folder\n")
    before = snapshot(files)
    for out in (notes / f"blob{ext}", notes / "sub" / f"blob{ext}"):
        proc = run_cli(cli, tmp_path, "sphere", files / "blob.blend", out)
        refused(proc, 1, f"paramorph sphere: error: cannot write {out}: {notes} is a file, not a folder")
        assert "Blob:" not in proc.stdout, output(proc)  # before the sphere map
    if os.path.isdir("/proc"):  # a folder that takes no new file, even for root
        out = f"/proc/paramorph-test{ext}"
        proc = run_cli(cli, tmp_path, "sphere", files / "blob.blend", out)
        refused(proc, 1, f"paramorph sphere: error: cannot write {out}: the folder /proc takes no new file")
        assert "Blob:" not in proc.stdout, output(proc)
    out = notes / f"blob{ext}"
    if ext == ".blend":
        proc = run_cli(cli, tmp_path, "morph", files / "blob.obj", files / "blob.blend", "-o", out)
        refused(proc, 1, f"paramorph morph: error: cannot write {out}: {notes} is a file, not a folder")
    proc = run_cli(cli, tmp_path, "paste", files / "blob.blend", files / "blob.obj", out,
                   "--select-ball", "0,0,0,1", "--at", "0,0,1")
    refused(proc, 1, f"paramorph paste: error: cannot write {out}: {notes} is a file, not a folder")
    assert snapshot(files) == before


def test_output_that_is_an_input_is_a_usage_error(cli, tmp_path):
    files = blob_files(tmp_path)
    blend, obj = files / "blob.blend", files / "blob.obj"
    os.symlink(blend, files / "link.blend")
    os.link(obj, files / "hard.obj")
    before = snapshot(files)
    ball = ["--select-ball", "0,0,0,1", "--at", "0,0,1"]
    for args, label in ((["sphere", os.path.relpath(blend), f"{files}/./blob.blend"], "IN"),
                        (["unwrap", files / "link.blend", blend], "IN"),                # a symbolic link
                        (["segment", obj, files / "hard.obj"], "IN"),                   # a hard link
                        (["sphere", obj, f"{files}/../files/blob.obj"], "IN"),
                        (["morph", obj, blend, "-o", files / "link.blend"], "B"),
                        (["morph", blend, obj, "-o", blend], "A"),
                        (["paste", blend, obj, f"{files}/./blob.blend", *ball], "SOURCE"),
                        (["paste", blend, obj, files / "hard.obj", *ball], "TARGET")):
        proc = run_cli(cli, tmp_path, *args)
        refused(proc, 2, f"is the same file as {label}: write the result to another file")
    assert snapshot(files) == before  # no input overwritten, no .blend1 backup


def test_output_that_is_a_folder_is_a_usage_error(cli, tmp_path):
    files = blob_files(tmp_path)
    for name in ("out.blend", "out.obj", "out.ply"):
        (files / name).mkdir()
        (files / name / "keep.txt").write_text("a file in a folder named like an output\n")
    before = snapshot(files)
    blend, obj = files / "blob.blend", files / "blob.obj"
    for args in (["sphere", blend, files / "out.blend"],
                 ["unwrap", obj, files / "out.obj"],
                 ["morph", obj, blend, "-o", files / "out.blend"],
                 ["paste", blend, obj, files / "out.ply", "--select-ball", "0,0,0,1", "--at", "0,0,1"]):
        proc = run_cli(cli, tmp_path, *args)
        refused(proc, 2, f"OUT '{args[-1] if args[0] != 'paste' else args[3]}' is a folder: name the file to write")
    assert snapshot(files) == before  # the folders not renamed to *.blend1, nothing written in them


def test_bad_blend_inputs_fail_in_plain_words(cli, tmp_path):
    files = blob_files(tmp_path)
    blend, obj = files / "blob.blend", files / "blob.obj"
    (files / "x.blend").write_text("this is not a blend file\n")
    (files / "broken.blend").write_bytes(blend.read_bytes()[:2000])  # cut short
    (files / "folder.blend").mkdir()
    before = snapshot(files)
    out = tmp_path / "out.blend"
    ball = ["--select-ball", "0,0,0,1", "--at", "0,0,1"]
    cases = {"x.blend": "is not a .blend file", "broken.blend": "cannot be read: ",
             "missing.blend": ": no such file", "folder.blend": "is a folder, not a file"}
    for name, message in cases.items():
        bad = files / name
        for args, label in ((["sphere", bad, out], None),
                            (["morph", obj, bad, "-o", out], "B"),
                            (["paste", bad, obj, out, *ball], "SOURCE")):
            proc = run_cli(cli, tmp_path, *args)
            assert proc.returncode == 1, output(proc)
            assert "Traceback" not in proc.stderr and "wrote" not in proc.stdout, output(proc)
            error = [line for line in proc.stderr.splitlines() if line.startswith(f"paramorph {args[0]}: error: ")]
            assert len(error) == 1 and name in error[0], output(proc)
            if label is not None:  # morph and paste say which input, and what is wrong with it
                assert f"error: {label}: " in error[0] and message in error[0], output(proc)
    proc = run_cli(cli, tmp_path, "morph", files / "x.blend", obj, "-o", out)
    refused(proc, 1, f"paramorph morph: error: A: {files / 'x.blend'} is not a .blend file")
    proc = run_cli(cli, tmp_path, "paste", blend, files / "broken.blend", out, *ball)
    refused(proc, 1, f"paramorph paste: error: TARGET: {files / 'broken.blend'} cannot be read: ")
    assert snapshot(files) == before and not out.exists()


def test_an_exporter_that_writes_nothing_is_an_error_and_out_stays(tmp_path, monkeypatch):
    """Blender's exporters may fail by only printing (3.4's OBJ exporter on a
    path it cannot open): save() checks what was written."""
    obj = make_samples.build_blob(subdivisions=1)
    out = tmp_path / "blob.obj"
    out.write_text("the previous result\n")
    # An operator that finishes and writes nothing stands in for the exporter.
    monkeypatch.setitem(paramorph_cli.EXPORTERS, ".obj", (("object", "select_all"),))
    with pytest.raises(paramorph_cli.CliError, match=f"cannot write {out}: Blender wrote nothing"):
        paramorph_cli.save(str(out), [obj], "unwrap")
    assert out.read_text() == "the previous result\n"
    assert [p.name for p in tmp_path.iterdir()] == ["blob.obj"]  # no temporary file left
    monkeypatch.undo()
    paramorph_cli.save(str(out), [obj], "unwrap")
    assert sum(line.startswith("v ") for line in out.read_text().splitlines()) == len(obj.data.vertices)
    assert [p.name for p in tmp_path.iterdir()] == ["blob.obj"]

    empty = tmp_path / "empty.obj"
    empty.write_bytes(b"")
    with pytest.raises(paramorph_cli.CliError, match="Blender wrote an empty file"):
        paramorph_cli.check_written(str(empty), str(out))
