"""Morph To and Preview Matches as a user runs them, inside real Blender: the
new object's topology, shape keys, keyframes, materials and UVs; the
previewed pairs, pins and their effect; bad input and cancel leave the scene
as it was."""
import bpy
import numpy as np
import pytest

import make_samples
from paramorph import jobs

pytestmark = pytest.mark.usefixtures("addon_scene")


def coordinates(data):
    co = np.empty(3 * len(data), dtype=np.float32)
    data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def select_pair(source, target):
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj in (source, target))
    bpy.context.view_layer.objects.active = target


def bbox(P):
    return np.vstack([P.min(axis=0), P.max(axis=0)])


def morph_pair(source_subdivisions=3):
    source = make_samples.build_blob(subdivisions=source_subdivisions)
    material = bpy.data.materials.new("BlobSkin")
    source.data.materials.append(material)
    bpy.ops.mesh.uv_texture_add()  # a UV layer to carry ("UVMap")
    target = make_samples.build_octopus(subdivisions=3, limbs=4)
    target.location = (4.0, 0.0, 0.0)
    select_pair(source, target)
    return source, target


def key_value_at(obj, key_name, frame):
    bpy.context.scene.frame_set(frame)
    return obj.data.shape_keys.key_blocks[key_name].value


def test_morph_to_builds_a_shape_keyed_object_on_the_merged_topology():
    source, target = morph_pair()
    objects_before = set(bpy.data.objects)
    assert bpy.ops.paramorph.morph_to(frame_start=1, frame_end=21, in_betweens=1, easing="LINEAR") == {"FINISHED"}
    (morph,) = set(bpy.data.objects) - objects_before
    assert bpy.context.view_layer.objects.active == morph and morph.name == "Blob to Octopus"
    mesh = morph.data
    keys = [k.name for k in mesh.shape_keys.key_blocks]
    assert keys == ["Basis", "Octopus 50%", "Octopus"]
    assert len(mesh.vertices) > len(source.data.vertices) and len(mesh.vertices) > len(target.data.vertices)
    # Basis is the source's surface, the last key the target's (in the source's place).
    basis = coordinates(mesh.shape_keys.key_blocks["Basis"].data)
    end = coordinates(mesh.shape_keys.key_blocks["Octopus"].data)
    np.testing.assert_allclose(bbox(basis), bbox(coordinates(source.data.vertices)), atol=1e-5)
    np.testing.assert_allclose(bbox(end), bbox(coordinates(target.data.vertices)), atol=1e-5)
    middle = coordinates(mesh.shape_keys.key_blocks["Octopus 50%"].data)
    np.testing.assert_allclose(middle, 0.5 * (basis + end), atol=1e-5)
    # Every merged face is a triangle; the mesh is closed (each edge in two faces).
    assert all(p.loop_total == 3 for p in mesh.polygons[:10])
    edge_faces = np.zeros(len(mesh.edges), dtype=np.int64)
    loop_edges = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("edge_index", loop_edges)
    np.add.at(edge_faces, loop_edges, 1)
    assert np.all(edge_faces == 2)
    # The source's look comes along.
    assert [m.name for m in mesh.materials] == ["BlobSkin"]
    assert "UVMap" in mesh.uv_layers
    # Tent keyframes: the in-between at full weight half way, the target at the end.
    assert key_value_at(morph, "Octopus 50%", 1) == pytest.approx(0.0)
    assert key_value_at(morph, "Octopus 50%", 11) == pytest.approx(1.0)
    assert key_value_at(morph, "Octopus", 11) == pytest.approx(0.0)
    assert key_value_at(morph, "Octopus", 16) == pytest.approx(0.5, abs=1e-3)
    assert key_value_at(morph, "Octopus", 21) == pytest.approx(1.0)
    # The inputs are untouched.
    assert source.data.shape_keys is None and target.data.shape_keys is None


def test_target_placement_ends_where_the_target_is():
    source, target = morph_pair()
    assert bpy.ops.paramorph.morph_to(placement="TARGET", use_features=False) == {"FINISHED"}
    morph = bpy.context.view_layer.objects.active
    end = coordinates(morph.data.shape_keys.key_blocks["Octopus"].data)
    world = end @ np.array(morph.matrix_world)[:3, :3].T + np.array(morph.matrix_world)[:3, 3]
    target_world = coordinates(target.data.vertices) + np.array(target.location)
    np.testing.assert_allclose(bbox(world), bbox(target_world), atol=1e-4)


def test_preview_matches_pins_and_morph_uses_them():
    source = make_samples.build_cad_part()
    target = make_samples.build_cad_part(name="CadPartB")
    target.location = (3.0, 0.0, 0.0)
    select_pair(source, target)
    assert bpy.ops.paramorph.preview_matches() == {"FINISHED"}
    matches = bpy.context.scene.paramorph_matches
    assert matches.source == source and matches.target == target
    automatic = [(p.vertex_a, p.vertex_b) for p in matches.pairs]
    assert automatic and not any(p.pin for p in matches.pairs)
    # The same part on both sides: every pair joins a vertex to its twin's place.
    A, B = coordinates(source.data.vertices), coordinates(target.data.vertices)
    diagonal = np.linalg.norm(np.ptp(A, axis=0))
    gaps = [np.linalg.norm(A[a] - B[b]) / diagonal for a, b in automatic]
    assert max(gaps) < 0.05, gaps
    assert source.paramorph_regions > 0 and target.paramorph_regions > 0

    # Pin vertex 0 of A to a vertex of B a tenth of the diagonal off its twin: the pin wins.
    far = int(np.argmin(np.abs(np.linalg.norm(B - A[0], axis=1) - 0.1 * diagonal)))
    for obj, vertex in ((source, 0), (target, far)):
        selected = np.zeros(len(obj.data.vertices), dtype=bool)
        selected[vertex] = True
        obj.data.vertices.foreach_set("select", selected)
    assert bpy.ops.paramorph.add_pin() == {"FINISHED"}
    assert sum(p.pin for p in matches.pairs) == 1
    assert bpy.ops.paramorph.remove_pair(index=len(matches.pairs) - 2) == {"FINISHED"}
    assert bpy.ops.paramorph.morph_to(use_features=True) == {"FINISHED"}
    morph = bpy.context.view_layer.objects.active
    basis = coordinates(morph.data.shape_keys.key_blocks["Basis"].data)
    end = coordinates(morph.data.shape_keys.key_blocks["CadPartB"].data)
    pinned = int(np.argmin(np.linalg.norm(basis - A[0], axis=1)))
    assert np.linalg.norm(basis[pinned] - A[0]) < 1e-6
    assert np.linalg.norm(end[pinned] - B[far]) / diagonal < 0.02


def test_a_mesh_with_a_hole_is_reported_by_name_and_nothing_is_added():
    source = make_samples.build_blob(subdivisions=3)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=6, y_subdivisions=6)
    grid = bpy.context.active_object
    select_pair(source, grid)
    objects_before = set(bpy.data.objects)
    with pytest.raises(RuntimeError, match=r"Grid: mesh has 1 hole"):
        bpy.ops.paramorph.morph_to()
    assert set(bpy.data.objects) == objects_before


def test_morph_needs_two_meshes_and_a_cancelled_run_adds_nothing(monkeypatch):
    source, target = morph_pair()
    source.select_set(False)
    assert not bpy.ops.paramorph.morph_to.poll()
    source.select_set(True)
    objects_before = set(bpy.data.objects)
    monkeypatch.setattr(jobs.NativeJob, "_progress", lambda self, fraction, stage: False)
    assert bpy.ops.paramorph.morph_to() == {"CANCELLED"}
    assert set(bpy.data.objects) == objects_before
