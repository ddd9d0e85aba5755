"""Morph To on a character made of several parts (issue 31): Suzanne's eyes
ride along her head through every key, in both topologies, keeping their
shape and their vertex groups (a rig still moves them); a part far from the
body stays where it was, and the report says which is which."""
import bpy
import numpy as np
import pytest
from mathutils import Quaternion

import make_samples
from paramorph import bridge
from paramorph.native import native
from test_morph_keep import coordinates, evaluated_positions, rigged, select_pair

pytestmark = pytest.mark.usefixtures("addon_scene")


def suzanne(name="Suzanne"):
    bpy.ops.mesh.primitive_monkey_add(size=2.0)
    obj = bpy.context.active_object
    obj.name = name
    return obj


def parts_of(obj):
    """(body vertices, [vertices of each other part]) by connected parts, the body the largest."""
    V, F = bridge.mesh_arrays(obj.data)[:2]
    labels = np.asarray(native.vertex_parts(F, len(V)))
    groups = sorted((np.flatnonzero(labels == k) for k in np.unique(labels)), key=len, reverse=True)
    return groups[0], groups[1:]


def assert_rides_along(rest, now, body, part, label):
    """The part keeps its shape (up to one uniform scale) and stays as close to
    the body as at rest, in proportion to the body's size."""
    i, j = np.triu_indices(len(part), 1)
    before = np.linalg.norm(rest[part][i] - rest[part][j], axis=1)
    after = np.linalg.norm(now[part][i] - now[part][j], axis=1)
    ratio = after / before
    assert np.ptp(ratio) < 1e-4 * ratio.mean(), label
    grow = np.linalg.norm(np.ptp(now[body], axis=0)) / np.linalg.norm(np.ptp(rest[body], axis=0))

    def gap(X):
        centre = X[part].mean(axis=0)
        return np.linalg.norm(X[body] - centre, axis=1).min()
    assert gap(now) <= 1.5 * grow * gap(rest) + 1e-3 * grow, label


def test_suzannes_eyes_ride_along_her_kept_topology_and_follow_the_rig(capfd):
    source = suzanne()
    target = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target.location = (5.0, 0.0, 0.0)
    armature = rigged(source)
    body, eyes = parts_of(source)
    assert len(eyes) == 2
    rest = coordinates(source.data.vertices)
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="KEEP", in_betweens=3, frame_start=1, frame_end=41) == {"FINISHED"}
    out, _ = capfd.readouterr()
    eye_vertices = sum(len(e) for e in eyes)
    assert f"2 separate parts of Suzanne ({eye_vertices} vertices) ride along its body" in out, out
    assert "removed 2 smaller parts" not in out, out
    blocks = source.data.shape_keys.key_blocks
    assert [k.name for k in blocks] == ["Basis", "Octopus 25%", "Octopus 50%", "Octopus 75%", "Octopus"]
    for key in blocks[1:]:
        now = coordinates(key.data)
        for eye in eyes:
            assert np.linalg.norm(now[eye] - rest[eye], axis=1).min() > 1e-3, f"{key.name}: left behind"
            assert_rides_along(rest, now, body, eye, key.name)
    # The eyes keep their vertex groups, so the bone still turns them with the head.
    assert all(len(source.data.vertices[int(v)].groups) == 1 for eye in eyes for v in eye)
    bpy.context.scene.frame_set(41)
    end = coordinates(blocks["Octopus"].data)
    pose_bone = armature.pose.bones["Body"]
    pose_bone.rotation_mode = "QUATERNION"
    pose_bone.rotation_quaternion = Quaternion((1.0, 0.0, 0.0), np.pi / 2)
    bpy.context.view_layer.update()
    turned = evaluated_positions(source)
    R = np.array(pose_bone.matrix)[:3, :3] @ np.array(armature.data.bones["Body"].matrix_local)[:3, :3].T
    scale = np.ptp(end, axis=0).max()
    for eye in eyes:
        np.testing.assert_allclose(turned[eye], end[eye] @ R.T, atol=1e-4 * scale)


def test_suzannes_eyes_are_in_the_merged_morph_and_ride_along(capfd):
    source = suzanne()
    source.rotation_euler = (0.3, 0.0, 1.1)  # as a scene turns it: the same answer
    target = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target.location = (5.0, 0.0, 0.0)
    _, eyes = parts_of(source)
    V, F, tri_poly, _ = bridge.mesh_arrays(source.data, polygons=True, loops=True)
    rest = coordinates(source.data.vertices)
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="MERGED", in_betweens=2) == {"FINISHED"}
    out, _ = capfd.readouterr()
    assert "2 separate parts of Suzanne" in out and "ride along its body" in out, out
    obj = bpy.data.objects["Suzanne to Octopus"]
    eye_vertices = np.concatenate(eyes)
    n = len(obj.data.vertices)
    # The eyes come last, in the source's order, with their own faces.
    basis = coordinates(obj.data.shape_keys.key_blocks["Basis"].data)
    tail = np.arange(n - len(eye_vertices), n)
    np.testing.assert_allclose(basis[tail], rest[np.sort(eye_vertices)], atol=1e-5)
    eye_faces = [p for p in obj.data.polygons if min(p.vertices) >= n - len(eye_vertices)]
    in_eyes = np.isin(F, eye_vertices).all(axis=1)
    assert len(eye_faces) == int(in_eyes.sum())
    body = np.arange(n - len(eye_vertices))
    order = {int(v): k for k, v in enumerate(np.sort(eye_vertices))}
    for key in obj.data.shape_keys.key_blocks[1:]:
        now = coordinates(key.data)
        for eye in eyes:
            rows = tail[[order[int(v)] for v in eye]]
            assert np.linalg.norm(now[rows] - basis[rows], axis=1).min() > 1e-3, key.name
            assert_rides_along(basis, now, body, rows, key.name)


def test_a_part_far_from_the_body_stays_where_it_was(capfd):
    source = suzanne()
    bpy.ops.mesh.primitive_cube_add(size=0.3, location=(0.0, 0.0, 8.0))
    source.select_set(True)
    bpy.context.view_layer.objects.active = source
    bpy.ops.object.join()  # one mesh: Suzanne, her eyes, and a cube well off her head
    target = make_samples.build_blob(name="Blob", subdivisions=3)
    target.location = (5.0, 0.0, 0.0)
    rest = coordinates(source.data.vertices)
    far = np.flatnonzero(rest[:, 2] > 6.0)
    assert len(far) == 8
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="KEEP", in_betweens=1) == {"FINISHED"}
    out, _ = capfd.readouterr()
    assert "2 separate parts of Suzanne" in out and "1 part of Suzanne far from its body stays where it was" in out, out
    for key in source.data.shape_keys.key_blocks[1:]:
        np.testing.assert_array_equal(coordinates(key.data)[far], rest[far])


def test_a_source_of_equal_pieces_says_which_is_morphed_and_loses_nothing(capfd):
    for i in range(6):  # six small cubes in a row, apart: no one main body
        bpy.ops.mesh.primitive_cube_add(size=0.2, location=(0.6 * i, 0.0, 0.0))
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.join()
    source = bpy.context.active_object
    source.name = "Pieces"
    target = make_samples.build_blob(name="Blob", subdivisions=3)
    target.location = (5.0, 0.0, 0.0)
    rest = coordinates(source.data.vertices)
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="KEEP", in_betweens=1) == {"FINISHED"}
    out, _ = capfd.readouterr()
    assert "the morph takes Pieces's largest part (8 of its 48 vertices) as its body" in out, out
    assert "5 parts of Pieces far from its body stay where they were" in out, out
    assert len(source.data.vertices) == 48
    end = coordinates(source.data.shape_keys.key_blocks["Blob"].data)
    moved = np.linalg.norm(end - rest, axis=1) > 1e-6
    assert moved.sum() == 8  # one cube became the blob's shape, the others kept theirs exactly
    np.testing.assert_array_equal(end[~moved], rest[~moved])


def test_open_ringed_and_intersecting_parts_ride_along_too(capfd):
    source = suzanne()
    bpy.ops.mesh.primitive_plane_add(size=0.5, location=(0.0, -0.9, 0.9), rotation=(1.2, 0.0, 0.0))  # open
    bpy.ops.mesh.primitive_torus_add(major_segments=16, minor_segments=6, major_radius=0.3, minor_radius=0.05,
                                     location=(0.0, 0.0, 1.0))  # genus 1
    bpy.ops.mesh.primitive_ico_sphere_add(radius=0.3, location=(0.6, 0.0, 0.0))  # through the head
    bpy.ops.object.select_all(action="SELECT")
    bpy.context.view_layer.objects.active = source
    bpy.ops.object.join()
    target = make_samples.build_blob(name="Blob", subdivisions=3)
    target.location = (5.0, 0.0, 0.0)
    body, parts = parts_of(source)
    assert len(parts) == 5  # two eyes, the plane, the torus, the sphere
    rest = coordinates(source.data.vertices)
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="KEEP", in_betweens=1) == {"FINISHED"}
    out, _ = capfd.readouterr()
    vertices = sum(len(p) for p in parts)
    assert f"5 separate parts of Suzanne ({vertices} vertices) ride along its body" in out, out
    # Each keeps its shape, moves, and stays near the body's surface (its
    # surface, not its nearest vertex: the kept body's vertices are spread
    # over the target): within twice its gap at rest, as the surface under a
    # floating part changes shape (the nose under the plane flattens).
    _, F = bridge.mesh_arrays(source.data)[:2]
    body_faces = F[np.isin(F, body).all(axis=1)]

    def gap(X, part):
        return np.abs(np.asarray(native.signed_distance(X, body_faces, X[part]))).min()
    for key in source.data.shape_keys.key_blocks[1:]:
        now = coordinates(key.data)
        grow = np.linalg.norm(np.ptp(now[body], axis=0)) / np.linalg.norm(np.ptp(rest[body], axis=0))
        for part in parts:
            assert np.linalg.norm(now[part] - rest[part], axis=1).min() > 1e-3, key.name
            i, j = np.triu_indices(len(part), 1)
            ratio = np.linalg.norm(now[part][i] - now[part][j], axis=1) / np.linalg.norm(rest[part][i] - rest[part][j], axis=1)
            assert np.ptp(ratio) < 1e-4 * ratio.mean(), key.name
            assert gap(now, part) <= 2.0 * grow * gap(rest, part) + 0.02 * grow, key.name


def test_the_targets_own_parts_are_said_to_be_left_out(capfd):
    source = make_samples.build_blob(name="Blob", subdivisions=3)
    target = suzanne("Monkey")
    target.location = (5.0, 0.0, 0.0)
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="MERGED", in_betweens=1) == {"FINISHED"}
    out, _ = capfd.readouterr()
    assert "Monkey's 2 smaller parts" in out and "are left out: the morph goes to its largest part" in out, out

