"""The sphere map as the demo writes it, checked inside real Blender: the
"Sphere" UV layer and shape key, save/reload, and nothing written on failure."""
import addon_utils
import bpy
import numpy as np
import pytest

import make_samples
from paramorph import bridge


pytestmark = pytest.mark.usefixtures("empty_scene")


def test_addon_enables_like_a_user_does():
    addon_utils.enable("paramorph", default_set=True)
    assert "paramorph" in bpy.context.preferences.addons
    assert bridge.native is not None, bridge.load_error


def uv_array(mesh, name):
    layer = mesh.uv_layers[name]
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2)


def test_sphere_uv_and_shape_key_on_the_blob(tmp_path):
    obj = make_samples.build_blob(subdivisions=4)
    mesh = obj.data
    result = bridge.sphere_map_object(obj)
    assert result.flipped == 0 and result.residual <= 1e-7

    uv = uv_array(mesh, "Sphere")
    assert np.all(uv >= -1e-6) and np.all(uv <= 1.5 + 1e-6)
    # Seam handled: no polygon stretches across the texture.
    loop_start = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", loop_start)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    u = uv[:, 0]
    spans = np.maximum.reduceat(u, loop_start) - np.minimum.reduceat(u, loop_start)
    # Only a face that contains a pole in its interior may still span more
    # (the longitude runs all the way round it): at most one per pole.
    assert np.count_nonzero(spans > 0.5) <= 2, np.sort(spans)[-5:]

    keys = mesh.shape_keys.key_blocks
    assert "Basis" in keys and "Sphere" in keys and keys["Sphere"].value == 0.0
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    keys["Sphere"].data.foreach_get("co", co)
    co = co.reshape(-1, 3).astype(np.float64)
    V, _, _, _ = bridge.mesh_arrays(mesh)
    center = 0.5 * (V.min(axis=0) + V.max(axis=0))
    radii = np.linalg.norm(co - center, axis=1)
    np.testing.assert_allclose(radii, radii.max(), rtol=1e-5)

    path = str(tmp_path / "sphere.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    reloaded = bpy.data.objects["Blob"].data
    assert "Sphere" in reloaded.uv_layers and "Sphere" in reloaded.shape_keys.key_blocks


def test_closed_suzanne_sample_maps_fold_free():
    obj = make_samples.build_suzanne_closed()
    V, F, _, _ = bridge.mesh_arrays(obj.data)
    assert bridge.require_native().validate(V, F).is_closed_genus0
    assert bridge.sphere_map_object(obj).flipped == 0


def test_open_mesh_raises_and_writes_nothing():
    pm = bridge.require_native()
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=6, y_subdivisions=6)
    obj = bpy.context.active_object
    with pytest.raises(pm.NotClosedError, match="not closed: it has 1 boundary loop"):
        bridge.sphere_map_object(obj)
    assert "Sphere" not in obj.data.uv_layers
    assert obj.data.shape_keys is None
