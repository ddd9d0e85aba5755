"""Morph To keeping the source's topology (issue 17): the target's shape as
shape keys on the rigged source object itself (armature, vertex groups, UVs),
which keeps its rig and deforms with it; scrubbing evaluates the in-between
keys; a target with more detail than the source is warned about, not
refused."""
import bpy
import numpy as np
import pytest
from mathutils import Quaternion

import make_samples
from paramorph import bridge
from paramorph.morph import operators as ops_morph
from paramorph.morph.result_object import MORPH_PROPERTY
from paramorph.native import native

pytestmark = pytest.mark.usefixtures("addon_scene")


def coordinates(data):
    co = np.empty(3 * len(data), dtype=np.float32)
    data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def evaluated_positions(obj):
    return coordinates(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.vertices)


def select_pair(source, target):
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj in (source, target))
    bpy.context.view_layer.objects.active = target


def rigged(source):
    """An armature with one bone at the origin along z parenting `source`
    (Armature modifier), every vertex in its group at weight 1, and a UV layer."""
    bpy.context.view_layer.objects.active = source
    bpy.ops.mesh.uv_texture_add()
    armature_data = bpy.data.armatures.new("Rig")
    armature = bpy.data.objects.new("Rig", armature_data)
    bpy.context.collection.objects.link(armature)
    bpy.context.view_layer.objects.active = armature
    bpy.ops.object.mode_set(mode="EDIT")
    bone = armature_data.edit_bones.new("Body")
    bone.head, bone.tail = (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    bpy.ops.object.mode_set(mode="OBJECT")
    group = source.vertex_groups.new(name="Body")
    group.add(list(range(len(source.data.vertices))), 1.0, "REPLACE")
    modifier = source.modifiers.new("Armature", "ARMATURE")
    modifier.object = armature
    source.parent = armature
    return armature


def state_of(obj):
    mesh = obj.data
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    mesh.uv_layers[0].data.foreach_get("uv", uv)
    return {"vertices": len(mesh.vertices), "faces": [tuple(p.vertices) for p in mesh.polygons],
            "uv": uv.tobytes(), "groups": [g.name for g in obj.vertex_groups],
            "weights": [(g.group, g.weight) for v in mesh.vertices for g in v.groups],
            "modifiers": [(m.name, m.type, getattr(getattr(m, "object", None), "name", None)) for m in obj.modifiers],
            "parent": obj.parent and obj.parent.name, "materials": [m and m.name for m in mesh.materials]}


def test_a_rigged_source_keeps_its_rig_and_deforms_with_it(capfd):
    source = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target = make_samples.build_blob(name="Blob", subdivisions=3)
    target.location = (4.0, 0.0, 0.0)
    armature = rigged(source)
    # A shape key the artist made before (a "Smile") stays as it is.
    source.shape_key_add(name="Basis", from_mix=False)
    smile = source.shape_key_add(name="Smile", from_mix=False)
    smile.value = 0.0  # off, as 3.4-4.5 add keys; 5.x adds them at full weight
    smile_co = coordinates(smile.data) + [0.0, 0.0, 0.1]
    smile.data.foreach_set("co", smile_co.astype(np.float32).ravel())
    before = state_of(source)
    VA, FA = bridge.mesh_arrays(source.data)[:2]
    VB, FB = bridge.mesh_arrays(target.data)[:2]
    objects_before = set(bpy.data.objects)
    select_pair(source, target)

    assert bpy.ops.paramorph.morph_to(frame_start=1, frame_end=91, easing="LINEAR") == {"FINISHED"}
    out, _ = capfd.readouterr()
    assert "Octopus keeps its topology" in out and "Hausdorff distance to the target" in out, out
    assert set(bpy.data.objects) == objects_before  # no new object
    assert state_of(source) == before  # topology, UVs, groups, weights, modifiers, parent untouched
    blocks = source.data.shape_keys.key_blocks
    assert [k.name for k in blocks] == ["Basis", "Smile"] + [f"Blob {p}%" for p in (11, 22, 33, 44, 56, 67, 78, 89)] + ["Blob"]
    np.testing.assert_allclose(coordinates(blocks["Smile"].data), smile_co, atol=1e-6)
    assert all(k.relative_key == blocks["Basis"] for k in blocks[1:])
    # The last key is the target sampled at the source's vertices through the
    # correspondence, then fitted to the target both ways (the matched tips held).
    morph = native.morph(VA, FA, VB, FB)
    sampled = np.asarray(morph.target)[np.asarray(morph.vertex_of_a)]
    held = np.unique(np.asarray(morph.pairs, dtype=np.int64).reshape(-1, 2)[:, 0])
    fit = native.fit_to_surface(sampled, FA, VB, FB, held=held)
    expected = np.asarray(fit.positions)
    end = coordinates(blocks["Blob"].data)
    # The faces left folded against the target are reported (noted over 1 %).
    assert ops_morph.last_morph["folded"] == pytest.approx(fit.facing_away_after)
    assert ("folded against the target" in out) == (fit.facing_away_after > ops_morph.FOLDED_SHARE), out
    scale = np.ptp(VB, axis=0).max()
    assert np.abs(end - expected).max() < 1e-4 * scale
    np.testing.assert_allclose(end[held], sampled[held], atol=1e-5 * scale)
    assert native.surface_distance(end, FA, VB, FB).hausdorff < native.surface_distance(sampled, FA, VB, FB).hausdorff
    np.testing.assert_allclose(coordinates(blocks["Basis"].data), VA, atol=1e-6)

    # Scrubbing: at t = 4/9 the evaluated mesh is that key's shape.
    bpy.context.scene.frame_set(41)
    assert source[MORPH_PROPERTY] == pytest.approx(4 / 9)
    np.testing.assert_allclose(evaluated_positions(source), coordinates(blocks["Blob 44%"].data), atol=1e-5 * scale)
    # The rig still drives it: the bone turned 90 degrees turns the morphed shape with it
    # (its pose matrix against its rest matrix; the bone's head is at the origin).
    bpy.context.scene.frame_set(91)
    rest = evaluated_positions(source)
    np.testing.assert_allclose(rest, end, atol=1e-5 * scale)
    pose_bone = armature.pose.bones["Body"]
    pose_bone.rotation_mode = "QUATERNION"
    pose_bone.rotation_quaternion = Quaternion((1.0, 0.0, 0.0), np.pi / 2)
    bpy.context.view_layer.update()
    turned = evaluated_positions(source)
    R = np.array(armature.pose.bones["Body"].matrix)[:3, :3] @ np.array(armature.data.bones["Body"].matrix_local)[:3, :3].T
    np.testing.assert_allclose(turned, end @ R.T, atol=1e-4 * scale)
    assert np.abs(turned - rest).max() > 0.1 * scale

    # Morph To again replaces its keys and timing (three in-betweens on straight
    # lines, frames 1-21), and a morph to another target replaces them too.
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(in_betweens=3, interpolation="LINEAR", frame_start=1,
                                      frame_end=21) == {"FINISHED"}
    assert [k.name for k in source.data.shape_keys.key_blocks] == ["Basis", "Smile", "Blob 25%", "Blob 50%", "Blob 75%", "Blob"]
    assert len(source.data.shape_keys.animation_data.drivers) == 4
    bpy.context.scene.frame_set(21)
    assert source[MORPH_PROPERTY] == pytest.approx(1.0)
    other = make_samples.build_blob(name="Other", subdivisions=2)
    other.location = (-4.0, 0.0, 0.0)
    select_pair(source, other)
    assert bpy.ops.paramorph.morph_to(in_betweens=1) == {"FINISHED"}
    assert [k.name for k in source.data.shape_keys.key_blocks] == ["Basis", "Smile", "Other 50%", "Other"]
    assert len(source.data.shape_keys.animation_data.drivers) == 2


def test_a_target_finer_than_the_source_is_warned_about_not_refused(capfd, monkeypatch):
    monkeypatch.setattr(ops_morph, "FOLDED_SHARE", -1.0)  # the folded faces' note whatever their share
    source = make_samples.build_blob(name="Coarse", subdivisions=1)
    target = make_samples.build_octopus(name="Octopus", subdivisions=4, limbs=6)
    target.location = (4.0, 0.0, 0.0)
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="KEEP", in_betweens=2) == {"FINISHED"}
    out, _ = capfd.readouterr()
    assert "Coarse is too coarse for Octopus's detail" in out and "Topology: Merged" in out, out
    assert f"{100 * ops_morph.last_morph['folded']:.2g} % of its faces lie folded against the target" in out, out
    assert [k.name for k in source.data.shape_keys.key_blocks] == ["Basis", "Octopus 33%", "Octopus 67%", "Octopus"]


def test_the_reported_distance_is_the_same_however_the_scene_is_turned():
    # The share is of the target's own box (target_turn: its object's
    # rotation), not of its turned copy's, which grows or shrinks with the
    # turn while the distance itself stays (the whole scene turned alike).
    from paramorph.morph import job as morph_job

    source = make_samples.build_octopus(name="Five", subdivisions=2, limbs=5)
    target = make_samples.build_octopus(name="Seven", subdivisions=4, limbs=7)
    VA, FA = bridge.mesh_arrays(source.data)[:2]
    VB, FB = bridge.mesh_arrays(target.data)[:2]
    u, _, vt = np.linalg.svd(np.array(Quaternion((1.0, 2.0, 0.5), 0.9).to_matrix(), dtype=np.float64))
    turn = u @ vt  # orthonormal to the last bit
    outcomes = [morph_job.morph_with_in_betweens(VA @ R.T, FA, VB @ R.T, FB, progress=lambda f, stage: True,
                                                 keep_topology=True, target_turn=R)
                for R in (np.eye(3), turn)]
    assert outcomes[1].target_diagonal == pytest.approx(outcomes[0].target_diagonal, rel=1e-9)
    assert outcomes[1].target_diagonal != pytest.approx(np.linalg.norm(np.ptp(VB @ turn.T, axis=0)), rel=1e-3)
    distances = [o.distance.hausdorff for o in outcomes]
    assert distances[0] > 0 and distances[1] == pytest.approx(distances[0], rel=1e-6), distances


def test_automatic_topology_follows_what_hangs_on_the_source():
    bare = make_samples.build_blob(name="Bare", subdivisions=3)
    target = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target.location = (4.0, 0.0, 0.0)
    while bare.data.uv_layers:  # a bare mesh: no UVs, groups or rig
        bare.data.uv_layers.remove(bare.data.uv_layers[0])
    assert not bare.vertex_groups and bare.find_armature() is None
    select_pair(bare, target)
    assert bpy.ops.paramorph.morph_to(in_betweens=1) == {"FINISHED"}
    assert "Bare to Octopus" in bpy.data.objects and bare.data.shape_keys is None  # merged: a new object
    bare.vertex_groups.new(name="Any")
    select_pair(bare, target)
    assert bpy.ops.paramorph.morph_to(in_betweens=1) == {"FINISHED"}
    assert [k.name for k in bare.data.shape_keys.key_blocks] == ["Basis", "Octopus 50%", "Octopus"]


def test_a_cancelled_keep_topology_morph_leaves_the_source_as_it_was(monkeypatch):
    """Cancelled during the native call or between in-betweens: no key, no
    property, no driver on the source."""
    from paramorph import jobs
    source = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target = make_samples.build_blob(name="Blob", subdivisions=3)
    target.location = (4.0, 0.0, 0.0)
    rigged(source)
    select_pair(source, target)
    for stop_at in (0.0, 0.9):  # in the morph; in the in-betweens (after 85 %)
        monkeypatch.setattr(jobs.NativeJob, "_progress", lambda self, fraction, stage: fraction < stop_at)
        assert bpy.ops.paramorph.morph_to(topology="KEEP") == {"CANCELLED"}
        assert source.data.shape_keys is None and MORPH_PROPERTY not in source
        assert source.animation_data is None or source.animation_data.action is None


def test_undo_takes_a_morph_back_and_redo_brings_it_again():
    """One undo step per Morph To, as the UI pushes it: keep topology takes
    back the keys, the property, its animation and drivers, the rest of the
    source untouched; merged takes back the new object. Redo brings them back."""
    source = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target = make_samples.build_blob(name="Blob", subdivisions=3)
    target.location = (4.0, 0.0, 0.0)
    rigged(source)
    source.shape_key_add(name="Basis", from_mix=False)
    source.shape_key_add(name="Smile", from_mix=False)
    before = state_of(source)
    objects_before = sorted(o.name for o in bpy.data.objects)
    select_pair(source, target)
    bpy.ops.ed.undo_push(message="Before Morph To")
    assert bpy.ops.paramorph.morph_to(topology="KEEP", in_betweens=2) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Morph To")
    assert MORPH_PROPERTY in bpy.data.objects["Octopus"]

    assert bpy.ops.ed.undo() == {"FINISHED"}
    source = bpy.data.objects["Octopus"]  # undo reloads the data: old references are gone
    assert [k.name for k in source.data.shape_keys.key_blocks] == ["Basis", "Smile"]
    assert MORPH_PROPERTY not in source
    assert source.animation_data is None or source.animation_data.action is None
    assert source.data.shape_keys.animation_data is None or not source.data.shape_keys.animation_data.drivers
    assert state_of(source) == before  # by name: undo reloads every datablock
    assert bpy.ops.ed.redo() == {"FINISHED"}
    source = bpy.data.objects["Octopus"]
    assert [k.name for k in source.data.shape_keys.key_blocks] == ["Basis", "Smile", "Blob 33%", "Blob 67%", "Blob"]
    assert MORPH_PROPERTY in source

    bpy.ops.ed.undo()  # back to before the keys, then a merged morph, undone
    select_pair(bpy.data.objects["Octopus"], bpy.data.objects["Blob"])
    bpy.ops.ed.undo_push(message="Before Morph To")
    assert bpy.ops.paramorph.morph_to(topology="MERGED", in_betweens=1) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Morph To")
    assert "Octopus to Blob" in bpy.data.objects
    assert bpy.ops.ed.undo() == {"FINISHED"}
    assert sorted(o.name for o in bpy.data.objects) == objects_before
