"""Morph To, Preview Matches and the pins as a user runs them, inside real
Blender: the new object's topology, shape keys, keyframes, materials and UVs;
a pin lands exactly on its partner; the candidates Preview Matches weighed;
pins saved with the .blend and used after reloading it; pins picked with the
Pick Pins tool's picker; errors (a vertex pinned twice, an edited index out
of range, a hole) reported by name with nothing added; an inside-out file
turned; cancel leaves the scene as it was."""
import math
import re

import bpy
import numpy as np
import pytest

import make_samples
from paramorph import jobs
from paramorph.morph.pins import PinPicker
from paramorph.morph.result_object import MORPH_PROPERTY
from paramorph.native import native

pytestmark = pytest.mark.usefixtures("addon_scene")


def coordinates(data):
    co = np.empty(3 * len(data), dtype=np.float32)
    data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def select_pair(source, target):
    if bpy.context.view_layer.objects.active is not None and bpy.context.view_layer.objects.active.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj in (source, target))
    bpy.context.view_layer.objects.active = target


def bbox(P):
    return np.vstack([P.min(axis=0), P.max(axis=0)])


def diagonal(P):
    return float(np.linalg.norm(np.ptp(P, axis=0)))


def morph_pair(source_subdivisions=3):
    """A blob (with a material and a UV layer to carry) and a four-armed octopus, 320 faces each."""
    source = make_samples.build_blob(subdivisions=source_subdivisions)
    material = bpy.data.materials.new("BlobSkin")
    source.data.materials.append(material)
    bpy.ops.mesh.uv_texture_add()  # a UV layer to carry ("UVMap")
    top = source.vertex_groups.new(name="Top")  # a vertex group to carry: the upper cap
    top.add([v.index for v in source.data.vertices if v.co.z > 0.3], 1.0, "REPLACE")
    target = make_samples.build_octopus(subdivisions=3, limbs=4)
    target.location = (4.0, 0.0, 0.0)
    select_pair(source, target)
    return source, target


def turned_octopus_pair():
    """Two four-armed octopuses, the target's mesh turned 45 degrees about z:
    as placed their arms miss each other, so an automatic candidate beats none."""
    source = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target = make_samples.build_octopus(name="OctopusB", subdivisions=3, limbs=4)
    target.rotation_euler[2] = math.radians(45.0)
    select_pair(target, target)
    bpy.ops.object.transform_apply(rotation=True)
    target.location = (4.0, 0.0, 0.0)
    select_pair(source, target)
    return source, target


def tip_pin(source, target):
    """(vertex of source, vertex of target) farthest along +x on each: the blob's
    side and the octopus's arm tip, a pin the morph can honour."""
    return (int(np.argmax(coordinates(source.data.vertices)[:, 0])),
            int(np.argmax(coordinates(target.data.vertices)[:, 0])))


def run_reported(capfd, op, **options):
    """Runs an operator and returns (its status, what it reported on stdout/stderr)."""
    capfd.readouterr()
    status = op(**options)
    out, err = capfd.readouterr()
    return status, out + err


def pin_gap(morph, source, target, vertex_a, vertex_b, target_key):
    """How far (share of the target's diagonal) the merged vertex at source
    vertex `vertex_a` ends from target vertex `vertex_b` in the last key."""
    A, B = coordinates(source.data.vertices), coordinates(target.data.vertices)
    keys = morph.data.shape_keys.key_blocks
    basis = coordinates(keys["Basis"].data)
    end = coordinates(keys[target_key].data)
    merged = int(np.argmin(np.linalg.norm(basis - A[vertex_a], axis=1)))
    assert np.linalg.norm(basis[merged] - A[vertex_a]) <= 1e-6 * diagonal(A)
    return np.linalg.norm(end[merged] - B[vertex_b]) / diagonal(B)


def key_value_at(obj, key_name, frame):
    bpy.context.scene.frame_set(frame)
    return obj.data.shape_keys.key_blocks[key_name].value


def test_morph_to_builds_a_shape_keyed_object_on_the_merged_topology(capfd):
    source, target = morph_pair()
    objects_before = set(bpy.data.objects)
    status, report = run_reported(capfd, bpy.ops.paramorph.morph_to, topology="MERGED", frame_start=1, frame_end=21,
                                  in_betweens=1, interpolation="LINEAR", easing="LINEAR")
    assert status == {"FINISHED"}
    # The report names the chosen candidate and its score, and what holds exactly.
    assert re.search(r"Morph To: Blob to Octopus, \d+ faces \([0-9.]+x the inputs' \d+\)[^;]*; chosen [\w ]+ — .*score [0-9.e+-]+; "
                     r"0 pins and \d+ pairs? held exactly", report), report
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
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    assert np.all(loop_total == 3)
    edge_faces = np.zeros(len(mesh.edges), dtype=np.int64)
    loop_edges = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("edge_index", loop_edges)
    np.add.at(edge_faces, loop_edges, 1)
    assert np.all(edge_faces == 2)
    # The source's look comes along, and its vertex groups: the weight of a
    # merged vertex interpolates the source's over the face holding it.
    assert [m.name for m in mesh.materials] == ["BlobSkin"]
    assert "UVMap" in mesh.uv_layers
    assert [g.name for g in morph.vertex_groups] == ["Top"]
    source_top = (coordinates(source.data.vertices)[:, 2] > 0.3).astype(float)
    merged_weight = np.zeros(len(mesh.vertices))
    for v in mesh.vertices:
        for g in v.groups:
            merged_weight[v.index] = g.weight
    # The source's vertices are merged vertices, with their own weights.
    assert 0 < source_top.sum() < len(source_top)
    at_source = [int(np.argmin(np.linalg.norm(basis - p, axis=1))) for p in coordinates(source.data.vertices)]
    np.testing.assert_allclose(merged_weight[at_source], source_top, atol=1e-6)
    assert np.all((merged_weight >= 0) & (merged_weight <= 1))
    assert np.any((merged_weight > 0.01) & (merged_weight < 0.99))  # interpolated along the group's edge
    # One property drives the keys (tent drivers, simple expressions: no Python
    # needed); it is keyframed 0 -> 1: the in-between at full weight half way,
    # the target at the end.
    drivers = morph.data.shape_keys.animation_data.drivers
    assert len(drivers) == 2 and all(d.driver.is_simple_expression for d in drivers)
    assert key_value_at(morph, "Octopus 50%", 1) == pytest.approx(0.0)
    assert key_value_at(morph, "Octopus 50%", 11) == pytest.approx(1.0)
    assert key_value_at(morph, "Octopus", 11) == pytest.approx(0.0)
    assert key_value_at(morph, "Octopus", 16) == pytest.approx(0.5, abs=1e-3)
    assert key_value_at(morph, "Octopus", 21) == pytest.approx(1.0)
    # The inputs are untouched.
    assert source.data.shape_keys is None and target.data.shape_keys is None


def evaluated_positions(obj):
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    return coordinates(evaluated.data.vertices)


def test_in_betweens_are_as_rigid_as_possible_and_scrubbing_plays_them():
    """The default in-betweens are the native as-rigid-as-possible ones (not
    the straight mix), eight of them; scrubbing the timeline shows each key's
    shape at its frame and a mix of neighbours between."""
    source, target = morph_pair()
    objects_before = set(bpy.data.objects)
    assert bpy.ops.paramorph.morph_to(topology="MERGED", frame_start=1, frame_end=91, easing="LINEAR") == {"FINISHED"}
    (morph,) = set(bpy.data.objects) - objects_before
    blocks = morph.data.shape_keys.key_blocks
    assert [k.name for k in blocks] == ["Basis"] + [f"Octopus {p}%" for p in (11, 22, 33, 44, 56, 67, 78, 89)] + ["Octopus"]
    basis, end = coordinates(blocks["Basis"].data), coordinates(blocks["Octopus"].data)
    faces = np.array([tuple(p.vertices) for p in morph.data.polygons], dtype=np.int32)
    expected = native.ShapeInterpolation(basis, end, faces).at(4 / 9)
    middle = coordinates(blocks["Octopus 44%"].data)
    scale = np.ptp(end, axis=0).max()
    assert np.abs(middle - expected).max() < 1e-4 * scale
    assert np.abs(middle - (5 / 9 * basis + 4 / 9 * end)).max() > 1e-3 * scale  # not the straight mix
    # Frame 41 is t = 4/9: the evaluated mesh is that key's shape; half way
    # between two keys' frames it is their mean.
    bpy.context.scene.frame_set(41)
    assert morph[MORPH_PROPERTY] == pytest.approx(4 / 9)
    np.testing.assert_allclose(evaluated_positions(morph), middle, atol=1e-5 * scale)
    bpy.context.scene.frame_set(46)
    after = coordinates(blocks["Octopus 56%"].data)
    np.testing.assert_allclose(evaluated_positions(morph), 0.5 * (middle + after), atol=1e-4 * scale)
    bpy.context.scene.frame_set(91)
    np.testing.assert_allclose(evaluated_positions(morph), end, atol=1e-5 * scale)


def test_target_placement_ends_where_the_target_is():
    source, target = morph_pair()
    assert bpy.ops.paramorph.morph_to(topology="MERGED", placement="TARGET", automatic=False) == {"FINISHED"}
    morph = bpy.context.view_layer.objects.active
    end = coordinates(morph.data.shape_keys.key_blocks["Octopus"].data)
    world = end @ np.array(morph.matrix_world)[:3, :3].T + np.array(morph.matrix_world)[:3, 3]
    target_world = coordinates(target.data.vertices) + np.array(target.location)
    np.testing.assert_allclose(bbox(world), bbox(target_world), atol=1e-4)


@pytest.mark.parametrize("topology", ["MERGED", "KEEP"])
def test_morph_to_respects_both_objects_rotation_and_scale(topology):
    # A target scaled x3 and turned 45 deg, a source scaled x2 and moved: the
    # morph ends at the target as it looks (issue 20: it ended at the
    # unscaled, unturned target), in the source's place or in the target's.
    import mathutils
    source, target = morph_pair()
    source.location, source.scale = (-2.0, 1.0, 0.5), (2.0, 2.0, 2.0)
    target.rotation_euler, target.scale = (0.0, 0.0, 0.785398), (3.0, 3.0, 3.0)
    bpy.context.view_layer.update()
    looks = coordinates(target.data.vertices) @ np.array(target.matrix_world)[:3, :3].T
    for placement, offset in (("SOURCE", np.array(source.location)), ("TARGET", np.array(target.location))):
        select_pair(source, target)
        assert bpy.ops.paramorph.morph_to(topology=topology, placement=placement, automatic=False,
                                          in_betweens=0) == {"FINISHED"}
        morph = bpy.context.view_layer.objects.active if topology == "MERGED" else source
        end = coordinates(morph.data.shape_keys.key_blocks["Octopus"].data)
        world = end @ np.array(morph.matrix_world)[:3, :3].T + np.array(morph.matrix_world)[:3, 3]
        tolerance = 1e-4 * np.ptp(looks, axis=0).max() if topology == "MERGED" else 0.1 * np.ptp(looks, axis=0).max()
        np.testing.assert_allclose(bbox(world), bbox(looks + offset), atol=tolerance)
        if topology == "KEEP":  # the Basis is the source as it was
            basis = coordinates(morph.data.shape_keys.key_blocks["Basis"].data)
            np.testing.assert_allclose(basis, coordinates(morph.data.vertices), atol=1e-6)


def test_a_pin_lands_exactly_on_its_partner(capfd):
    source, target = morph_pair()
    a, b = tip_pin(source, target)
    assert bpy.ops.paramorph.add_pin(vertex_a=a, vertex_b=b) == {"FINISHED"}
    matches = bpy.context.scene.paramorph_matches
    assert [(p.vertex_a, p.vertex_b, p.pin) for p in matches.pairs] == [(a, b, True)]
    assert matches.source == source and matches.target == target
    status, report = run_reported(capfd, bpy.ops.paramorph.morph_to, topology="MERGED", automatic=False)
    assert status == {"FINISHED"} and "1 pin and 0 pairs held exactly" in report, report
    morph = bpy.context.view_layer.objects.active
    assert pin_gap(morph, source, target, a, b, "Octopus") <= 1e-6


def test_add_pin_checks_its_vertices_and_replaces_pairs_on_them():
    source, target = morph_pair()
    with pytest.raises(RuntimeError, match=r"Octopus has no vertex 100000 \(it has \d+\)"):
        bpy.ops.paramorph.add_pin(vertex_a=0, vertex_b=100000)
    # Without indices: the one selected vertex of each object.
    with pytest.raises(RuntimeError, match=r"select exactly one vertex on Blob \(\d+ selected\)"):
        bpy.ops.paramorph.add_pin(vertex_b=3)
    selected = np.zeros(len(source.data.vertices), dtype=bool)
    selected[5] = True
    source.data.vertices.foreach_set("select", selected)
    assert bpy.ops.paramorph.add_pin(vertex_b=3) == {"FINISHED"}
    # A new pin on a vertex already pinned replaces the old pin.
    assert bpy.ops.paramorph.add_pin(vertex_a=5, vertex_b=9) == {"FINISHED"}
    assert bpy.ops.paramorph.add_pin(vertex_a=6, vertex_b=10) == {"FINISHED"}
    matches = bpy.context.scene.paramorph_matches
    assert [(p.vertex_a, p.vertex_b) for p in matches.pairs] == [(5, 9), (6, 10)]
    assert bpy.ops.paramorph.remove_pair(index=0) == {"FINISHED"}
    assert [(p.vertex_a, p.vertex_b) for p in matches.pairs] == [(6, 10)]


def test_preview_matches_shows_the_candidates_keeps_the_pins_and_morph_uses_its_pairs(capfd):
    source, target = turned_octopus_pair()
    a, b = tip_pin(source, target)
    assert bpy.ops.paramorph.add_pin(vertex_a=a, vertex_b=b) == {"FINISHED"}
    status, report = run_reported(capfd, bpy.ops.paramorph.preview_matches)
    assert status == {"FINISHED"}
    matches = bpy.context.scene.paramorph_matches
    candidates = list(matches.candidates)
    assert len(candidates) >= 2 and {c.kind for c in candidates} >= {"none"}
    chosen = [c for c in candidates if c.chosen]
    assert len(chosen) == 1, [(c.kind, c.chosen) for c in candidates]
    scored = [c.score for c in candidates if not c.rejected]
    assert chosen[0].score == min(scored) and not chosen[0].rejected
    assert all(c.detail for c in candidates)
    # The one-line report says the same, and what "none" scored.
    line = f"Preview Matches: chosen {chosen[0].kind} — {chosen[0].detail}, score "
    assert line in report, report
    if chosen[0].kind != "none":
        assert "(no pairs: " in report, report
    # The pin was kept (first), the automatic pairs came with their candidate's kind.
    pins = [(p.vertex_a, p.vertex_b) for p in matches.pairs if p.pin]
    automatic = [p for p in matches.pairs if not p.pin]
    assert pins == [(a, b)]
    assert automatic, "the turned octopus's arms should be paired"
    assert all(p.kind == chosen[0].kind for p in automatic)
    assert all(p.vertex_a != a and p.vertex_b != b for p in automatic)
    # Nothing is written on the objects any more (no region attributes).
    assert "paramorph_region" not in source.data.attributes
    assert "paramorph_region" not in target.data.attributes

    # Clear Pins keeps the automatic pairs; the morph uses the previewed pairs as edited.
    assert bpy.ops.paramorph.remove_pair(index=len(matches.pairs) - 1) == {"FINISHED"}
    kept = [(p.vertex_a, p.vertex_b) for p in matches.pairs if not p.pin]
    status, report = run_reported(capfd, bpy.ops.paramorph.morph_to, topology="MERGED")
    assert status == {"FINISHED"}
    assert re.search(rf"previewed pairs given — {len(kept)} pairs?.*1 pin and {len(kept)} pairs? held exactly",
                     report), report
    morph = bpy.context.view_layer.objects.active
    for vertex_a, vertex_b in [(a, b)] + kept:
        assert pin_gap(morph, source, target, vertex_a, vertex_b, "OctopusB") <= 1e-6
    select_pair(source, target)
    assert bpy.ops.paramorph.clear_pins() == {"FINISHED"}
    assert not any(p.pin for p in matches.pairs) and len(matches.pairs) == len(kept)


def test_pins_are_saved_with_the_file_and_used_after_reloading(tmp_path):
    source, target = morph_pair()
    a, b = tip_pin(source, target)
    assert bpy.ops.paramorph.add_pin(vertex_a=a, vertex_b=b) == {"FINISHED"}
    path = str(tmp_path / "pins.blend")
    assert bpy.ops.wm.save_as_mainfile(filepath=path) == {"FINISHED"}
    bpy.ops.wm.read_homefile(use_empty=True, app_template="")
    assert len(bpy.context.scene.paramorph_matches.pairs) == 0
    assert bpy.ops.wm.open_mainfile(filepath=path) == {"FINISHED"}
    matches = bpy.context.scene.paramorph_matches
    source, target = bpy.data.objects["Blob"], bpy.data.objects["Octopus"]
    assert matches.source == source and matches.target == target
    assert [(p.vertex_a, p.vertex_b, p.pin) for p in matches.pairs] == [(a, b, True)]
    select_pair(source, target)
    assert bpy.ops.paramorph.morph_to(topology="MERGED", automatic=False) == {"FINISHED"}
    morph = bpy.context.view_layer.objects.active
    assert pin_gap(morph, source, target, a, b, "Octopus") <= 1e-6


def test_a_vertex_pinned_twice_is_reported_and_nothing_is_added():
    source, target = morph_pair()
    assert bpy.ops.paramorph.add_pin(vertex_a=1, vertex_b=2) == {"FINISHED"}
    assert bpy.ops.paramorph.add_pin(vertex_a=3, vertex_b=4) == {"FINISHED"}
    matches = bpy.context.scene.paramorph_matches
    matches.pairs[1].vertex_a = 1  # edited in the panel's list
    objects_before = set(bpy.data.objects)
    with pytest.raises(RuntimeError, match=r"Blob → Octopus: pins 0 and 1 both pin vertex 1 of A"):
        bpy.ops.paramorph.morph_to(topology="MERGED")
    assert set(bpy.data.objects) == objects_before
    # An index edited past the mesh's end is reported by object and pin, not as a traceback.
    matches.pairs[1].vertex_a = 3
    matches.pairs[1].vertex_b = 99999
    with pytest.raises(RuntimeError, match=r"pin 1 \(3, 99999\): Octopus has no vertex 99999"):
        bpy.ops.paramorph.morph_to(topology="MERGED")
    assert set(bpy.data.objects) == objects_before


def test_pins_picked_on_other_geometry_are_an_error_not_ignored():
    source, target = morph_pair()
    assert bpy.ops.paramorph.add_pin(vertex_a=1, vertex_b=2) == {"FINISHED"}
    bpy.data.objects.remove(source)
    source = make_samples.build_blob(name="Blob", subdivisions=2)  # fewer vertices now
    bpy.context.scene.paramorph_matches.source = source
    select_pair(source, target)
    with pytest.raises(RuntimeError, match=r"pins of Blob → Octopus were picked on 162 and \d+ vertices"):
        bpy.ops.paramorph.morph_to(topology="MERGED")


def test_an_inside_out_target_is_turned_and_the_report_says_so(capfd):
    source, target = morph_pair()
    select_pair(target, target)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.flip_normals()
    bpy.ops.object.mode_set(mode="OBJECT")
    for repair, note in ((False, "Octopus's faces pointed inwards: turned for the morph"),
                         (True, "Octopus repaired: turned 1 inside-out part the right way out")):
        select_pair(source, target)
        status, report = run_reported(capfd, bpy.ops.paramorph.morph_to, topology="MERGED", automatic=False,
                                      repair=repair)
        assert status == {"FINISHED"}, report
        assert note in report, report
        assert "Blob's faces" not in report and "Blob repaired" not in report
        morph = bpy.context.view_layer.objects.active
        end = coordinates(morph.data.shape_keys.key_blocks["Octopus"].data)
        np.testing.assert_allclose(bbox(end), bbox(coordinates(target.data.vertices)), atol=1e-5)


def test_pick_pins_picker_pins_the_vertices_under_the_rays_and_takes_them_back():
    """The Pick Pins tool's picking state, driven with rays as the modal tool
    drives it with the mouse (the modal tool itself: tests/gui)."""
    from paramorph.morph import pin_store
    source, target = morph_pair()
    a, b = tip_pin(source, target)
    matches = pin_store.claim(bpy.context.scene.paramorph_matches, source, target)
    picker = PinPicker(source, target)

    def ray_to(obj, vertex):
        """A ray from far out along +x onto `vertex` of `obj`, in each object's coordinates."""
        point = obj.matrix_world @ obj.data.vertices[vertex].co
        origin = point.copy()
        origin.x += 20.0

        def ray_for(other):
            to_local = other.matrix_world.inverted()
            direction = (to_local.to_3x3() @ (point - origin)).normalized()
            return to_local @ origin, direction
        return ray_for

    assert picker.under(ray_to(source, a)) == (0, a)
    assert picker.under(ray_to(target, b)) == (1, b)
    assert picker.click(matches, (1, b)) is None and picker.pending == (1, b)  # target first
    assert picker.marks()["pending"] is not None
    assert picker.click(matches, (0, a)) == (a, b) and picker.pending is None
    assert [(p.vertex_a, p.vertex_b, p.pin) for p in matches.pairs] == [(a, b, True)]
    assert picker.click(matches, (0, 7)) is None
    picker.undo(matches)  # drops the half-picked pin
    assert picker.pending is None and len(matches.pairs) == 1
    picker.undo(matches)  # takes the pin back
    assert len(matches.pairs) == 0
    assert picker.click(matches, None) is None and "no vertex there" in picker.message
    # Without a 3D View (here: -b) the tool says where it works.
    with pytest.raises(RuntimeError, match="Pick Pins works in the 3D Viewport"):
        bpy.ops.paramorph.pick_pins()


def test_a_mesh_with_a_hole_is_reported_by_name_and_nothing_is_added():
    source = make_samples.build_blob(subdivisions=3)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=6, y_subdivisions=6)
    grid = bpy.context.active_object
    select_pair(source, grid)
    objects_before = set(bpy.data.objects)
    with pytest.raises(RuntimeError, match=r"Grid: mesh has 1 hole.*, or turn on Repair"):
        bpy.ops.paramorph.morph_to(topology="MERGED", repair=False)
    with pytest.raises(RuntimeError, match=r"Grid: mesh has 1 hole.*, or turn on Repair"):
        bpy.ops.paramorph.preview_matches(repair=False)
    assert set(bpy.data.objects) == objects_before


def test_morph_needs_two_meshes_and_a_cancelled_run_adds_nothing(monkeypatch):
    source, target = morph_pair()
    source.select_set(False)
    assert not bpy.ops.paramorph.morph_to.poll()
    assert not bpy.ops.paramorph.pick_pins.poll()
    source.select_set(True)
    objects_before = set(bpy.data.objects)
    monkeypatch.setattr(jobs.NativeJob, "_progress", lambda self, fraction, stage: False)
    assert bpy.ops.paramorph.morph_to(topology="MERGED") == {"CANCELLED"}
    assert bpy.ops.paramorph.preview_matches() == {"CANCELLED"}
    assert set(bpy.data.objects) == objects_before
    assert len(bpy.context.scene.paramorph_matches.candidates) == 0


MODELS = __import__("pathlib").Path(__file__).resolve().parents[3] / "shared" / "models"


@pytest.mark.skipif(not (MODELS / "samba.obj").exists() or not (MODELS / "dancer.obj").exists(),
                    reason="no ../shared/models")
def test_morph_to_between_two_real_people_stood_side_by_side_works_both_ways(capfd):
    # Issue 29: a woman in a skirt and a dancer (20k and 14k faces), as an
    # artist imports them; before, Morph To failed both ways blaming OpenCL.
    people = []
    for name in ("samba", "dancer"):
        before = set(bpy.data.objects)
        bpy.ops.wm.obj_import(filepath=str(MODELS / f"{name}.obj"))
        (person,) = set(bpy.data.objects) - before
        people.append(person)
    people[1].location.x += 2 * max(people[0].dimensions)
    for source, target in (people, people[::-1]):
        select_pair(source, target)
        objects_before = set(bpy.data.objects)
        status, report = run_reported(capfd, bpy.ops.paramorph.morph_to, topology="MERGED")
        assert status == {"FINISHED"}, report
        assert "OpenCL" not in report and f"Morph To: {source.name} to {target.name}" in report, report
        (morph,) = set(bpy.data.objects) - objects_before
        assert len(morph.data.vertices) >= len(source.data.vertices)
